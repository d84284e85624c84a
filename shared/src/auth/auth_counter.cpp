#include "socc/auth/auth_counter.hpp"

#include <algorithm>
#include <chrono>

namespace socc::auth {

namespace {
std::int64_t nowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
}  // namespace

AuthCounter::AuthCounter() : last_(nowMicros()) {}

std::int64_t AuthCounter::next() {
  last_ = std::max(last_ + 1, nowMicros());
  return last_;
}

}  // namespace socc::auth
