#pragma once
// Motion compensation within one sweep. The sensor moves with the body twist xi (per second,
// translation first) during the sweep, so a point taken at time t lies, in the sensor frame at
// reference_time, at exp((t - reference_time) * xi) * p.
#include <Eigen/Geometry>
#include <vector>

#include "socc/odom/se3.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

/// The sweep's motion as a map from a point and its time to where it lies at reference_time:
/// deskewing one point at a time, without a copy of the cloud (e.g. while downsampling it).
/// The motion is evaluated exactly at a few hundred instants over the sweep's times and
/// interpolated linearly in between (second-order error, below 1e-6 of the motion per sweep).
class SweepMotion {
 public:
  SweepMotion(const LabeledCloud& cloud, const Vector6d& twist, double reference_time);
  /// No motion to apply: the cloud has no times, or the twist is zero.
  bool identity() const { return knots_.empty(); }
  /// Point p taken at time (not identity()).
  Eigen::Vector3f operator()(const Eigen::Vector3f& p, float time) const;

 private:
  double t0_ = 0.0;
  double step_ = 1.0;
  std::vector<Eigen::Matrix<double, 3, 4>> knots_;
};

/// Returns the cloud with deskewed points (labels and times kept). A cloud without times is
/// returned unchanged.
LabeledCloud deskew(const LabeledCloud& cloud, const Vector6d& twist, double reference_time);

/// The middle of the sweep, (min + max) / 2 of the per-point times (0 without times). Poses
/// registered at this instant do not depend, to first order, on the twist used to deskew:
/// a twist error stretches the scan symmetrically about it instead of shifting it, which is what
/// keeps the closed loop of deskew and registration from oscillating (docs/robustness.md).
double sweepMidTime(const LabeledCloud& cloud);

}  // namespace socc::odom
