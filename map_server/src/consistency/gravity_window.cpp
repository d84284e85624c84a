#include "gravity_window.hpp"

#include <algorithm>
#include <cmath>

namespace socc::consistency {

void GravityWindow::start(const Eigen::Isometry3d& keyframe_pose,
                          const std::optional<GravityReference>& own) {
  *this = GravityWindow();
  keyframe_rotation_ = keyframe_pose.linear();
  if (own) take(own->up, own->sigma);
}

void GravityWindow::add(const Eigen::Isometry3d& pose,
                        const std::optional<GravityReference>& reading) {
  if (!keyframe_rotation_ || !reading) return;
  const Eigen::Vector3d up = keyframe_rotation_->transpose() * pose.linear() * reading->up;
  // A reading far from the others is not one of them: the robot's pose jumped (relocalized)
  // within the window, or the sensor glitched.
  const double sigma = std::max(sigma_, reading->sigma);
  if (sum_.squaredNorm() > 0.0 &&
      std::acos(std::clamp(sum_.normalized().dot(up), -1.0, 1.0)) > kMaxSigmas * sigma)
    return;
  take(up, reading->sigma);
  ++after_;
}

std::optional<GravityReference> GravityWindow::reference() const {
  if (after_ == 0) return std::nullopt;
  return gravityReference(sum_, sigma_);
}

void GravityWindow::take(const Eigen::Vector3d& up_in_keyframe, double sigma) {
  sum_ += up_in_keyframe;
  sigma_ = std::max(sigma_, sigma);
}

}  // namespace socc::consistency
