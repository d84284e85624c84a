#include "socc/pose_conversion.hpp"

#include <cmath>

namespace socc {

pose3d_t toLcm(const Eigen::Isometry3d& pose) {
  pose3d_t out;
  const Eigen::Quaterniond q(pose.linear());
  for (int i = 0; i < 3; ++i) out.translation[i] = pose.translation()[i];
  out.quaternion[0] = q.w();
  out.quaternion[1] = q.x();
  out.quaternion[2] = q.y();
  out.quaternion[3] = q.z();
  return out;
}

Eigen::Isometry3d fromLcm(const pose3d_t& pose) {
  const Eigen::Quaterniond q(pose.quaternion[0], pose.quaternion[1], pose.quaternion[2],
                             pose.quaternion[3]);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = q.normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(pose.translation[0], pose.translation[1], pose.translation[2]);
  return out;
}

std::string checkPose(const pose3d_t& pose, double max_abs_translation) {
  double qn = 0.0;
  for (const double v : pose.quaternion) {
    if (!std::isfinite(v)) return "pose quaternion is not finite";
    qn += v * v;
  }
  for (const double v : pose.translation) {
    if (!std::isfinite(v)) return "pose translation is not finite";
    if (std::abs(v) > max_abs_translation) return "pose translation is out of the map bounds";
  }
  if (std::abs(std::sqrt(qn) - 1.0) > 1e-3) return "pose quaternion is not unit length";
  return {};
}

}  // namespace socc
