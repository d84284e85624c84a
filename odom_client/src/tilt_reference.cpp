#include "socc/odom/tilt_reference.hpp"

#include <algorithm>
#include <cmath>

namespace socc::odom {

double TiltReference::predicted(double time) const {
  const double dt = time_ >= 0.0 ? std::max(time - time_, 0.0) : 0.0;
  return variance_ + walk_ * walk_ * dt;
}

double TiltReference::gain(double predicted_variance, double sigma) {
  return predicted_variance / (predicted_variance + sigma * sigma);
}

std::optional<TiltPrior> TiltReference::prior(const Eigen::Vector3d& up_at_mid, double sigma,
                                              double time) const {
  if (walk_ <= 0.0 || sigma <= 0.0 || up_sum_.squaredNorm() == 0.0) return std::nullopt;
  const double p = predicted(time);
  TiltPrior out;
  out.map_up = up_sum_.normalized();
  out.sensor_up = up_at_mid.normalized();
  out.gain = gain(p, sigma);
  return out;
}

void TiltReference::update(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& up_at_mid,
                           double sigma, double time) {
  if (walk_ <= 0.0 || sigma <= 0.0) return;
  // The update with the gain prior() gave this frame (none before the map's up is known).
  const double p = predicted(time);
  variance_ = up_sum_.squaredNorm() > 0.0 ? (1.0 - gain(p, sigma)) * p : 0.0;
  time_ = time;
  // The map's up: the mean of the first second's frames (the reference's white noise averages
  // out while the odometry has had no time to drift). Later frames would pull it along with the
  // odometry's own tilt drift, the very error the reference is there to hold.
  if (start_ < 0.0) start_ = time;
  if (time - start_ <= kUpWindow) up_sum_ += rotation * up_at_mid.normalized();
}

}  // namespace socc::odom
