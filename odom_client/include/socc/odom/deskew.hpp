#pragma once
// Motion compensation within one sweep. The sensor moves with the body twist xi (per second,
// translation first) during the sweep, so a point taken at time t lies, in the sensor frame at
// reference_time, at exp((t - reference_time) * xi) * p.
#include <Eigen/Geometry>

#include "socc/odom/se3.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

/// Returns the cloud with deskewed points (labels and times kept). A cloud without times is
/// returned unchanged.
LabeledCloud deskew(const LabeledCloud& cloud, const Vector6d& twist, double reference_time);

/// The middle of the sweep, (min + max) / 2 of the per-point times (0 without times). Poses
/// registered at this instant do not depend, to first order, on the twist used to deskew:
/// a twist error stretches the scan symmetrically about it instead of shifting it, which is what
/// keeps the closed loop of deskew and registration from oscillating (docs/robustness.md).
double sweepMidTime(const LabeledCloud& cloud);

}  // namespace socc::odom
