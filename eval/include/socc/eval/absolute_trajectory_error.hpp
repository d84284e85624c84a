#pragma once
// Absolute trajectory error (ATE) after rigid alignment, as `evo_ape -a`: the estimate's
// positions are aligned to the ground truth with the least-squares SE(3) transform
// (Umeyama without scale), then the per-pose error is |t_gt - t_aligned_est|. Also without the
// alignment: where the estimate is in the ground truth's own frame, e.g. robots that start at
// their true pose in a shared map, an offset alignment would hide is an error of the map.
#include <vector>

#include "socc/eval/error_statistics.hpp"
#include "socc/kitti_io.hpp"

namespace socc::eval {

struct AbsoluteTrajectoryError {
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // est -> gt
  Poses aligned_estimate;
  std::vector<double> errors;  // [m], one per pose
  ErrorStatistics stats;
  ErrorStatistics unaligned;  // of |t_gt - t_est| in the ground truth's frame
};

/// Least-squares rigid transform T minimising sum |gt_i - T est_i|^2 over the positions.
Eigen::Isometry3d alignPositions(const Poses& gt, const Poses& est);

/// gt and est must have the same, non-zero size (std::invalid_argument otherwise).
AbsoluteTrajectoryError computeAbsoluteTrajectoryError(const Poses& gt, const Poses& est);

}  // namespace socc::eval
