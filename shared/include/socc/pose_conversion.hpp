#pragma once
// Conversions between Eigen rigid transforms and the wire type socc::pose3d_t.
#include <Eigen/Geometry>
#include <string>

#include "socc/pose3d_t.hpp"

namespace socc {

pose3d_t toLcm(const Eigen::Isometry3d& pose);
Eigen::Isometry3d fromLcm(const pose3d_t& pose);
/// Empty when the pose is finite, has |t| <= max_abs_translation and a unit quaternion
/// (|q| within 1e-3 of 1); otherwise the reason.
std::string checkPose(const pose3d_t& pose, double max_abs_translation);

}  // namespace socc
