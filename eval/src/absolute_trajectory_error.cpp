#include "socc/eval/absolute_trajectory_error.hpp"

#include <Eigen/Geometry>
#include <stdexcept>

namespace socc::eval {

namespace {

Eigen::Matrix3Xd positions(const Poses& poses) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i)
    m.col(static_cast<Eigen::Index>(i)) = poses[i].translation();
  return m;
}

void checkSizes(const Poses& gt, const Poses& est) {
  if (gt.empty()) throw std::invalid_argument("ATE: empty trajectory");
  if (gt.size() != est.size())
    throw std::invalid_argument("ATE needs as many estimated poses (" + std::to_string(est.size()) +
                                ") as ground-truth poses (" + std::to_string(gt.size()) + ")");
}

}  // namespace

Eigen::Isometry3d alignPositions(const Poses& gt, const Poses& est) {
  checkSizes(gt, est);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (gt.size() == 1) {  // only a translation is determined
    t.translation() = gt.front().translation() - est.front().translation();
    return t;
  }
  t.matrix() = Eigen::umeyama(positions(est), positions(gt), /*with_scaling=*/false);
  return t;
}

AbsoluteTrajectoryError computeAbsoluteTrajectoryError(const Poses& gt, const Poses& est) {
  AbsoluteTrajectoryError ate;
  ate.alignment = alignPositions(gt, est);
  ate.aligned_estimate.reserve(est.size());
  ate.errors.reserve(est.size());
  for (std::size_t i = 0; i < est.size(); ++i) {
    ate.aligned_estimate.push_back(ate.alignment * est[i]);
    ate.errors.push_back((gt[i].translation() - ate.aligned_estimate.back().translation()).norm());
  }
  ate.stats = computeStatistics(ate.errors);
  std::vector<double> unaligned;
  unaligned.reserve(est.size());
  for (std::size_t i = 0; i < est.size(); ++i)
    unaligned.push_back((gt[i].translation() - est[i].translation()).norm());
  ate.unaligned = computeStatistics(unaligned);
  return ate;
}

}  // namespace socc::eval
