#include "socc/auth/auth_counter.hpp"

#include <algorithm>

#include "socc/wall_clock.hpp"

namespace socc::auth {

AuthCounter::AuthCounter() : last_(nowMicros()) {}

std::int64_t AuthCounter::next() {
  last_ = std::max(last_ + 1, nowMicros());
  return last_;
}

}  // namespace socc::auth
