#include "socc/sim/road_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "route_geometry.hpp"
#include "socc/sim/planar_cells.hpp"

namespace socc::sim {
namespace {

constexpr double kWindowStep = 1.0;      // [m] windows start every metre
constexpr std::size_t kWindowSpan = 10;  // steps a window spans

double worstRevisit(const Poses& poses, const std::vector<double>& s, double radius,
                    double min_path) {
  PlanarCells earlier(radius);
  double worst = 0.0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Vector3d p = poses[j].translation();
    earlier.visitNear(p.head<2>(), radius, [&](std::uint32_t i) {
      const Eigen::Vector3d q = poses[i].translation();
      if (s[j] - s[i] >= min_path && (p - q).head<2>().norm() < radius)
        worst = std::max(worst, std::abs(p.z() - q.z()));
      return false;
    });
    earlier.add(p.head<2>(), static_cast<std::uint32_t>(j));
  }
  return worst;
}

}  // namespace

RoadFit roadFit(const Poses& poses, double revisit_radius, double min_path) {
  RoadFit fit;
  if (poses.size() < 2) return fit;
  const RouteGeometry g = routeGeometry(poses);
  fit.worst_revisit = worstRevisit(poses, g.s, revisit_radius, min_path);
  const auto m = static_cast<std::size_t>(std::floor(g.s.back() / kWindowStep)) + 1;
  if (m <= kWindowSpan) return fit;
  const std::vector<double> height = alongPath(g.s, heightsOf(poses), kWindowStep, m);
  const std::vector<double> attitude = alongPath(g.s, g.attitude_grade, kWindowStep, m);
  std::vector<double> difference;
  for (std::size_t q = 0; q + kWindowSpan < m; ++q) {
    const double grade = (height[q + kWindowSpan] - height[q]) / (kWindowStep * kWindowSpan);
    double mean_attitude = 0.0;
    for (std::size_t k = q; k <= q + kWindowSpan; ++k)
      mean_attitude += attitude[k] / (kWindowSpan + 1);
    difference.push_back(mean_attitude - grade);
    fit.steepest = std::max(fit.steepest, std::abs(grade));
  }
  double mean = 0.0;
  for (const double d : difference) mean += d / static_cast<double>(difference.size());
  double squares = 0.0;
  for (const double d : difference) squares += (d - mean) * (d - mean);
  fit.grade_rms = std::atan(std::sqrt(squares / static_cast<double>(difference.size())));
  return fit;
}

RoadReport roadReport(const Poses& recorded, const RoadHeightModel& model) {
  RoadReport report{roadFit(recorded), {}, fuseRoadHeights(recorded, model)};
  report.road = roadFit(report.heights.poses);
  return report;
}

}  // namespace socc::sim
