#pragma once
// Motion compensation with the constant-velocity model (as KISS-ICP): the sensor moves by
// frame_motion (previous-to-current relative pose) per frame_period, so a point taken at time t
// is moved into the sensor frame at reference_time by exp((t - reference_time) / frame_period *
// log(frame_motion)).
#include <Eigen/Geometry>

#include "socc/point_cloud.hpp"

namespace socc::odom {

/// Returns the cloud with deskewed points (labels and times kept). A cloud without times, or a
/// non-positive frame_period, is returned unchanged.
LabeledCloud deskew(const LabeledCloud& cloud, const Eigen::Isometry3d& frame_motion,
                    double frame_period, double reference_time);

}  // namespace socc::odom
