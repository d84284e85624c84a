#include "socc/odom/adaptive_threshold.hpp"

#include <algorithm>
#include <cmath>

namespace socc::odom {

AdaptiveThreshold::AdaptiveThreshold(double initial_threshold, double min_motion, double max_range)
    : initial_threshold_(initial_threshold), min_motion_(min_motion), max_range_(max_range) {}

double AdaptiveThreshold::sigma() const {
  return samples_ == 0 ? initial_threshold_ : std::sqrt(sum_squares_ / samples_);
}

void AdaptiveThreshold::update(const Eigen::Isometry3d& correction) {
  const double error = modelError(correction, max_range_);
  if (error > min_motion_) {
    sum_squares_ += error * error;
    ++samples_;
  }
}

void AdaptiveThreshold::reset() {
  sum_squares_ = 0.0;
  samples_ = 0;
}

double AdaptiveThreshold::modelError(const Eigen::Isometry3d& correction, double max_range) {
  const double cos_theta = std::clamp((correction.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
  const double theta = std::acos(cos_theta);
  return correction.translation().norm() + 2.0 * max_range * std::sin(theta / 2.0);
}

}  // namespace socc::odom
