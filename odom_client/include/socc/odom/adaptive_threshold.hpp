#pragma once
// KISS-ICP's adaptive correspondence threshold: sigma is the RMS of the model errors (how far
// the registration moved away from the constant-velocity prediction), counting only corrections
// larger than min_motion; until the first such sample sigma = initial_threshold.
#include <Eigen/Geometry>

namespace socc::odom {

class AdaptiveThreshold {
 public:
  AdaptiveThreshold(double initial_threshold, double min_motion, double max_range);

  /// sigma [m]; correspondences are searched within 3 sigma, the robust kernel uses sigma / 3.
  double sigma() const;
  /// False until a motion-model error has been measured (sigma is still initial_threshold).
  bool calibrated() const { return samples_ > 0; }
  /// Feeds the correction prediction^-1 * estimate of the last frame.
  void update(const Eigen::Isometry3d& correction);
  void reset();

  /// Translation plus the worst-case displacement of a point at max_range by the rotation.
  static double modelError(const Eigen::Isometry3d& correction, double max_range);

 private:
  double initial_threshold_;
  double min_motion_;
  double max_range_;
  double sum_squares_ = 0.0;
  int samples_ = 0;
};

}  // namespace socc::odom
