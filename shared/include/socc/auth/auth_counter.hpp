#pragma once
// Client-side source of auth_counter values: strictly increasing and seeded with the wall
// clock in microseconds, so a restarted client (which has forgotten its last counter) still
// sends counters above everything the server has accepted from it before.
#include <cstdint>

namespace socc::auth {

class AuthCounter {
 public:
  AuthCounter();  // starts at the current time [us since epoch]
  explicit AuthCounter(std::int64_t last) : last_(last) {}

  /// max(last + 1, now in us): never repeats, follows the clock when idle.
  std::int64_t next();
  std::int64_t last() const { return last_; }

 private:
  std::int64_t last_;
};

}  // namespace socc::auth
