#pragma once
// stderr logging that cannot be turned into a flood by hostile traffic: at most
// max_per_second lines, then one summary of how many were suppressed.
#include <chrono>
#include <cstdint>
#include <string>

namespace socc::service {

class RateLimitedLog {
 public:
  explicit RateLimitedLog(bool enabled, int max_per_second = 5)
      : enabled_(enabled), max_per_second_(max_per_second) {}
  void warn(const std::string& message);

 private:
  bool enabled_;
  int max_per_second_;
  int in_window_ = 0;
  std::int64_t suppressed_ = 0;
  std::chrono::steady_clock::time_point window_start_{};
};

}  // namespace socc::service
