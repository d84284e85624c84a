#pragma once
// Fairness between robots: every client id gets a budget of `rate` requests per second of one
// expensive service (a token bucket holding at most `burst` requests). A request beyond its
// budget is refused with RESOURCE_EXHAUSTED before any work is done, so one flooding or
// misbehaving robot cannot take the server's single thread away from the others. The limit
// bites under contention only: while no other robot has asked within the last second, a robot
// alone (e.g. replaying a recording as fast as possible) is served at whatever rate it asks.
#include <chrono>
#include <cstddef>
#include <string>
#include <unordered_map>

namespace socc::service {

class RobotRateLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  /// rate <= 0: no limit. At most max_clients buckets are kept (full ones are forgotten first).
  RobotRateLimiter(double rate, double burst, std::size_t max_clients = 4096);

  /// True when client may make one more request at now (it is taken from its budget; a client
  /// beyond its budget is admitted while no other client made a request within a second).
  bool admit(const std::string& client, Clock::time_point now);
  double rate() const { return rate_; }

 private:
  struct Bucket {
    double tokens = 0.0;
    Clock::time_point last;
  };
  double refilled(const Bucket& bucket, Clock::time_point now) const;
  void forgetIdle(Clock::time_point now);
  bool othersActive(const std::string& client, Clock::time_point now) const;

  double rate_;
  double burst_;
  std::size_t max_clients_;
  std::unordered_map<std::string, Bucket> buckets_;
};

}  // namespace socc::service
