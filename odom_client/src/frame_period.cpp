#include "socc/odom/frame_period.hpp"

#include <algorithm>
#include <vector>

namespace socc::odom {

void FramePeriod::add(double dt) {
  if (!(dt > 0.0)) return;
  recent_.push_back(dt);
  if (recent_.size() > kRecent) recent_.pop_front();
}

double FramePeriod::period() const {
  if (recent_.empty()) return assumed_;
  // The lower median: of one period and one gap, the period.
  std::vector<double> sorted(recent_.begin(), recent_.end());
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>((sorted.size() - 1) / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  return *mid;
}

double FramePeriod::periods(double dt) const {
  const double p = period();
  return p > 0.0 ? std::max(1.0, dt / p) : 1.0;
}

}  // namespace socc::odom
