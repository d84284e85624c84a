#include "socc/sim/road_heights.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "route_geometry.hpp"
#include "socc/sim/planar_cells.hpp"

namespace socc::sim {
namespace {

// A later pose j on a street an earlier pose i drove: the road at j is the earlier pass's road
// at i's arc length moved on by j's offset along i's heading (the earlier pass's own heights
// give the rise, so neither the attitude nor the sensor's pitch enters).
struct RevisitPair {
  double s_earlier;
  std::size_t j;
};

std::vector<RevisitPair> revisitPairs(const Poses& poses, const RouteGeometry& g,
                                      const RoadHeightModel& p) {
  PlanarCells earlier(p.radius);
  std::vector<RevisitPair> pairs;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Vector2d xy = poses[j].translation().head<2>();
    std::optional<RevisitPair> best;
    double best_distance = p.radius;
    earlier.visitNear(xy, p.radius, [&](std::uint32_t i) {
      const Eigen::Vector2d offset = xy - poses[i].translation().head<2>();
      const double distance = offset.norm();
      if (g.s[j] - g.s[i] < p.min_path || distance >= best_distance) return false;
      const double along = g.heading[i] ? offset.dot(*g.heading[i]) : 0.0;
      best = RevisitPair{std::clamp(g.s[i] + along, 0.0, g.s.back()), j};
      best_distance = distance;
      return false;
    });
    if (best) pairs.push_back(*best);
    earlier.add(xy, static_cast<std::uint32_t>(j));
  }
  return pairs;
}

// A function of arc length sampled every kStep metres.
constexpr double kStep = 0.5;

// Least squares over a few unknowns at a time: each row adds weight * (sum a_i x_i - target)^2.
class NormalEquations {
 public:
  explicit NormalEquations(Eigen::Index n) : n_(n), b_(Eigen::VectorXd::Zero(n)) {}
  void add(std::initializer_list<std::pair<Eigen::Index, double>> row, double target,
           double weight) {
    for (const auto& [i, ai] : row) {
      b_[i] += weight * ai * target;
      for (const auto& [j, aj] : row) h_.emplace_back(i, j, weight * ai * aj);
    }
  }
  Eigen::VectorXd solve() const {
    Eigen::SparseMatrix<double> h(n_, n_);
    h.setFromTriplets(h_.begin(), h_.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(h);
    if (solver.info() != Eigen::Success)
      throw std::runtime_error("fuseRoadHeights: the height corrections' system is singular");
    return solver.solve(b_);
  }

 private:
  Eigen::Index n_;
  Eigen::VectorXd b_;
  std::vector<Eigen::Triplet<double>> h_;
};

// The height correction along the path (every kStep metres of arc length, 0 at the start): the
// road's grade follows the attitude but for the sensor's constant pitch against the road (KITTI's
// LiDAR: 0.5-1.0 deg nose down, which integrates to metres per 300 m), its heights the recorded
// ones up to an offset (GPS errors are mostly a slowly wandering offset), its grade bends gently
// (so suspension pitch is smoothed out), and the passes of every revisit meet.
struct Corrections {
  std::vector<double> along_path;  // every kStep metres
  double pitch = 0.0;              // the sensor's pitch against the road, as a grade
};

Corrections solveCorrections(const Poses& poses, const RouteGeometry& g,
                             const std::vector<RevisitPair>& pairs, const RoadHeightModel& p) {
  const auto m = static_cast<std::size_t>(std::floor(g.s.back() / kStep)) + 2;
  const std::vector<double> height = alongPath(g.s, heightsOf(poses), kStep, m);
  const std::vector<double> attitude = alongPath(g.s, g.attitude_grade, kStep, m);
  const std::vector<double> facing = alongPath(g.s, g.facing, kStep, m);
  const auto offset = static_cast<Eigen::Index>(m);  // unknowns: the corrections, then these two
  const Eigen::Index pitch = offset + 1;
  NormalEquations equations(pitch + 1);
  equations.add({{0, 1.0}}, 0.0, 1e8);
  equations.add({{pitch, 1.0}}, 0.0, 1.0 / (p.pitch_sigma * p.pitch_sigma));
  const double gps = kStep / (p.gps_sigma * p.gps_sigma);
  const double grade = kStep / (p.grade_sigma * p.grade_sigma);
  const double bend = kStep / (p.bend_sigma * p.bend_sigma);
  const double h2 = kStep * kStep;
  for (std::size_t q = 0; q < m; ++q) {
    const auto i = static_cast<Eigen::Index>(q);
    equations.add({{i, 1.0}, {offset, -1.0}}, 0.0, gps);
    if (q + 1 == m) break;
    const double recorded_grade = (height[q + 1] - height[q]) / kStep;
    const double attitude_grade = 0.5 * (attitude[q] + attitude[q + 1]);
    const double sign = 0.5 * (facing[q] + facing[q + 1]);
    equations.add({{i, -1.0 / kStep}, {i + 1, 1.0 / kStep}, {pitch, sign}},
                  attitude_grade - recorded_grade, grade);
    if (q == 0) continue;
    const double recorded_bend = (height[q - 1] - 2.0 * height[q] + height[q + 1]) / h2;
    equations.add({{i - 1, 1.0 / h2}, {i, -2.0 / h2}, {i + 1, 1.0 / h2}}, -recorded_bend, bend);
  }
  const double revisit = 1.0 / (p.revisit_sigma * p.revisit_sigma);
  for (const RevisitPair& r : pairs) {
    const auto at = [m](double s) {
      const SampleBracket b = bracketOf(m, kStep, s);
      return std::pair{static_cast<Eigen::Index>(b.before), b.fraction};
    };
    const auto [i, ti] = at(r.s_earlier);
    const auto [j, tj] = at(g.s[r.j]);
    const double difference =
        sampleAt(height, kStep, r.s_earlier) - sampleAt(height, kStep, g.s[r.j]);
    equations.add({{j, 1.0 - tj}, {j + 1, tj}, {i, ti - 1.0}, {i + 1, -ti}}, difference, revisit);
  }
  const Eigen::VectorXd u = equations.solve();
  return {{u.data(), u.data() + offset}, u[pitch]};
}

}  // namespace

RoadHeights fuseRoadHeights(const Poses& poses, const RoadHeightModel& model) {
  RoadHeights out{poses, std::vector<double>(poses.size(), 0.0), 0, 0.0};
  if (poses.size() < 2) return out;
  const RouteGeometry g = routeGeometry(poses);
  const std::vector<RevisitPair> pairs = revisitPairs(poses, g, model);
  out.revisit_pairs = pairs.size();
  const Corrections correction = solveCorrections(poses, g, pairs, model);
  out.sensor_pitch = std::atan(correction.pitch);
  const std::vector<double>& u = correction.along_path;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out.change[k] = sampleAt(u, kStep, g.s[k]) - sampleAt(u, kStep, 0.0);
    out.poses[k].translation().z() += out.change[k];
    out.max_change = std::max(out.max_change, std::abs(out.change[k]));
  }
  return out;
}

}  // namespace socc::sim
