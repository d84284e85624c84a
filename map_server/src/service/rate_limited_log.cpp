#include "rate_limited_log.hpp"

#include <iostream>

namespace socc::service {

void RateLimitedLog::warn(const std::string& message) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - window_start_ >= std::chrono::seconds(1)) {
    if (suppressed_ > 0)
      std::cerr << "map_server: (" << suppressed_ << " similar warnings suppressed)\n";
    window_start_ = now;
    in_window_ = 0;
    suppressed_ = 0;
  }
  if (in_window_ >= max_per_second_) {
    ++suppressed_;
    return;
  }
  ++in_window_;
  std::cerr << "map_server: " << message << '\n';
}

}  // namespace socc::service
