#pragma once
// Frame-to-frame relative pose error (RPE), as `evo_rpe` with delta = 1 frame: for each pair
// (i, i+1) the error is E_i = (gt_i^-1 gt_i+1)^-1 (est_i^-1 est_i+1); the translational error is
// |trans(E_i)| [m], the rotational error angle(E_i) [deg].
#include <vector>

#include "socc/eval/error_statistics.hpp"
#include "socc/kitti_io.hpp"

namespace socc::eval {

struct RelativePoseError {
  std::vector<double> translation_errors;  // [m], one per frame pair
  std::vector<double> rotation_errors;     // [deg]
  ErrorStatistics translation;
  ErrorStatistics rotation;
};

/// gt and est must have the same size >= 2 (std::invalid_argument otherwise).
RelativePoseError computeRelativePoseError(const Poses& gt, const Poses& est);

}  // namespace socc::eval
