#pragma once
// One evaluation of an estimated trajectory against ground truth: KITTI metrics, ATE and RPE,
// with a human-readable table and a JSON form.
#include <iosfwd>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "socc/eval/absolute_trajectory_error.hpp"
#include "socc/eval/kitti_metrics.hpp"
#include "socc/eval/relative_pose_error.hpp"

namespace socc::eval {

struct EvaluationOptions {
  std::vector<double> lengths = kittiDefaultLengths();
  std::size_t step = 10;  // KITTI first-frame step [frames]
};

struct Evaluation {
  std::size_t frames = 0;
  double gt_length = 0.0;  // [m]
  KittiMetrics kitti;
  AbsoluteTrajectoryError ate;
  RelativePoseError rpe;
};

/// gt and est must have the same size >= 2 (std::invalid_argument otherwise).
Evaluation evaluate(const Poses& gt, const Poses& est, const EvaluationOptions& options = {});

void printTable(std::ostream& out, const Evaluation& e);
nlohmann::json toJson(const Evaluation& e);

}  // namespace socc::eval
