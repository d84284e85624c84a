#include "socc/eval/evaluation.hpp"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

namespace socc::eval {

namespace {

nlohmann::json statsJson(const ErrorStatistics& s) {
  return {{"count", s.count}, {"mean", s.mean}, {"median", s.median}, {"min", s.min},
          {"max", s.max},     {"rmse", s.rmse}, {"std", s.std}};
}

void printStatsRow(std::ostream& out, const std::string& name, const ErrorStatistics& s) {
  out << std::left << std::setw(22) << name << std::right << std::fixed << std::setprecision(4)
      << std::setw(10) << s.mean << std::setw(10) << s.median << std::setw(10) << s.max
      << std::setw(10) << s.rmse << std::setw(10) << s.std << '\n';
}

}  // namespace

Evaluation evaluate(const Poses& gt, const Poses& est, const EvaluationOptions& options) {
  Evaluation e;
  e.frames = gt.size();
  e.rpe = computeRelativePoseError(gt, est);  // checks sizes first
  e.gt_length = trajectoryDistances(gt).back();
  e.kitti = computeKittiMetrics(gt, est, options.lengths, options.step);
  e.ate = computeAbsoluteTrajectoryError(gt, est);
  return e;
}

void printTable(std::ostream& out, const Evaluation& e) {
  out << "frames: " << e.frames << ", ground-truth path length: " << std::fixed
      << std::setprecision(1) << e.gt_length << " m\n\n";
  out << "KITTI odometry metrics (" << e.kitti.segments.size() << " segments)\n";
  if (e.kitti.valid()) {
    out << std::setprecision(3) << "  t_err: " << e.kitti.t_err_percent << " %\n"
        << "  r_err: " << e.kitti.r_err_deg_per_100m << " deg/100m\n";
  } else {
    out << "  n/a: the trajectory is shorter than the shortest sub-sequence length"
           " (see --lengths)\n";
  }
  out << "  " << std::setw(10) << "length[m]" << std::setw(10) << "segments" << std::setw(12)
      << "t_err[%]" << std::setw(18) << "r_err[deg/100m]" << '\n';
  for (const auto& l : e.kitti.per_length) {
    out << "  " << std::setw(10) << std::setprecision(0) << l.length << std::setw(10) << l.segments;
    if (l.segments > 0)
      out << std::setprecision(3) << std::setw(12) << l.t_err_percent << std::setw(18)
          << l.r_err_deg_per_100m;
    out << '\n';
  }
  out << '\n'
      << std::left << std::setw(22) << "" << std::right << std::setw(10) << "mean" << std::setw(10)
      << "median" << std::setw(10) << "max" << std::setw(10) << "rmse" << std::setw(10) << "std"
      << '\n';
  printStatsRow(out, "ATE (SE3-aligned) [m]", e.ate.stats);
  printStatsRow(out, "ATE (unaligned) [m]", e.ate.unaligned);
  printStatsRow(out, "RPE trans [m]", e.rpe.translation);
  printStatsRow(out, "RPE rot [deg]", e.rpe.rotation);
}

nlohmann::json toJson(const Evaluation& e) {
  nlohmann::json per_length = nlohmann::json::array();
  for (const auto& l : e.kitti.per_length) {
    nlohmann::json j = {{"length_m", l.length}, {"segments", l.segments}};
    if (l.segments > 0) {
      j["t_err_percent"] = l.t_err_percent;
      j["r_err_deg_per_100m"] = l.r_err_deg_per_100m;
    }
    per_length.push_back(j);
  }
  nlohmann::json kitti = {{"segments", e.kitti.segments.size()}, {"per_length", per_length}};
  if (e.kitti.valid()) {
    kitti["t_err_percent"] = e.kitti.t_err_percent;
    kitti["r_err_deg_per_100m"] = e.kitti.r_err_deg_per_100m;
  }
  return {{"frames", e.frames},
          {"gt_length_m", e.gt_length},
          {"kitti", kitti},
          {"ate_m", statsJson(e.ate.stats)},
          {"ate_unaligned_m", statsJson(e.ate.unaligned)},
          {"rpe_trans_m", statsJson(e.rpe.translation)},
          {"rpe_rot_deg", statsJson(e.rpe.rotation)}};
}

}  // namespace socc::eval
