#pragma once
// The odometry's tilt held to a gravity reference (an IMU's or INS's up), as IMU-aided LiDAR
// odometry does (odom_client/README.md "Gravity reference"). Scan-to-map registration measures
// each pose against a map whose own tilt is every earlier frame's error summed, so pitch and
// roll drift like a random walk however well each scan fits. A one-dimensional Kalman filter
// per tilt axis says how far to trust the registration against the reference: the odometry's
// tilt error grows by `walk` per square root of a second, the reference's is its stated sigma;
// each frame's gain K becomes the reference's weight in the registration (TiltPrior).
#include <Eigen/Core>
#include <optional>

#include "socc/odom/registration.hpp"

namespace socc::odom {

class TiltReference {
 public:
  /// walk: [rad / sqrt(s)] how fast the odometry's tilt drifts without a reference; 0: off.
  explicit TiltReference(double walk) : walk_(walk) {}
  /// The prior for a scan whose reference is up_at_mid (the sensor's up at the pose's instant,
  /// sensor frame) with gravity's sigma, at time [s]; none before the map's up is known, or when
  /// off.
  std::optional<TiltPrior> prior(const Eigen::Vector3d& up_at_mid, double sigma, double time) const;
  /// A registered frame: rotation map_R_sensor at the instant of up_at_mid. Applies the filter's
  /// update with the gain prior() gave (none: 0); in the first second its up (map frame) joins
  /// the map's.
  void update(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& up_at_mid, double sigma,
              double time);
  /// The map frame turned by rotation (new_R_old; an own-frame robot merged): so did its up.
  void moveFrame(const Eigen::Matrix3d& rotation) { up_sum_ = rotation * up_sum_; }
  /// [rad^2] the odometry's tilt error variance per axis after the last update.
  double variance() const { return variance_; }

 private:
  // The filter's prediction at time: the last variance plus the walk since then.
  double predicted(double time) const;
  // The Kalman gain of a prediction with that variance against a reference of that sigma.
  static double gain(double predicted_variance, double sigma);
  static constexpr double kUpWindow = 1.0;  // [s] the frames whose up defines the map's
  double walk_;
  Eigen::Vector3d up_sum_ = Eigen::Vector3d::Zero();  // sum of those frames' up, map frame
  double variance_ = 0.0;  // the first frame defines the map's up: no error yet
  double time_ = -1.0;     // [s] of the last update
  double start_ = -1.0;    // [s] of the first
};

}  // namespace socc::odom
