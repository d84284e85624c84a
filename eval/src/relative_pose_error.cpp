#include "socc/eval/relative_pose_error.hpp"

#include <cmath>
#include <stdexcept>

#include "socc/eval/kitti_metrics.hpp"

namespace socc::eval {

RelativePoseError computeRelativePoseError(const Poses& gt, const Poses& est) {
  if (gt.size() != est.size())
    throw std::invalid_argument("RPE needs as many estimated poses (" + std::to_string(est.size()) +
                                ") as ground-truth poses (" + std::to_string(gt.size()) + ")");
  if (gt.size() < 2) throw std::invalid_argument("RPE needs at least 2 poses");
  RelativePoseError rpe;
  for (std::size_t i = 0; i + 1 < gt.size(); ++i) {
    const Eigen::Isometry3d delta_gt = gt[i].inverse() * gt[i + 1];
    const Eigen::Isometry3d delta_est = est[i].inverse() * est[i + 1];
    const Eigen::Isometry3d error = delta_gt.inverse() * delta_est;
    rpe.translation_errors.push_back(error.translation().norm());
    rpe.rotation_errors.push_back(rotationAngle(error) * 180.0 / M_PI);
  }
  rpe.translation = computeStatistics(rpe.translation_errors);
  rpe.rotation = computeStatistics(rpe.rotation_errors);
  return rpe;
}

}  // namespace socc::eval
