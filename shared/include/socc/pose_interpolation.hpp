#pragma once
// Interpolation between two rigid transforms as the consistency service and the revised
// trajectory use it for corrections: translation linearly, rotation by slerp (not the screw
// motion of odom/se3.hpp: a correction is a frame change, not a motion).
#include <Eigen/Geometry>

namespace socc {

/// a at s = 0, b at s = 1.
inline Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                         double s) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(a.linear())
                     .slerp(s, Eigen::Quaterniond(b.linear()))
                     .normalized()
                     .toRotationMatrix();
  out.translation() = (1.0 - s) * a.translation() + s * b.translation();
  return out;
}

}  // namespace socc
