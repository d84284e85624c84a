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

#include "socc/sim/planar_cells.hpp"

namespace socc::sim {
namespace {

// The route as driven: horizontal arc length, direction of travel (none while standing), the
// road's grade along it by the recorded attitude (the slope of the sensor's x-y plane) and the
// way the sensor faces (+1 forwards, -1 reversing: a sensor pitched against the road tilts the
// grade it gives by that sign).
struct RouteGeometry {
  std::vector<double> s;
  std::vector<std::optional<Eigen::Vector2d>> heading;
  std::vector<double> attitude_grade;
  std::vector<double> facing;
};

double attitudeGrade(const Eigen::Isometry3d& pose, const std::optional<Eigen::Vector2d>& heading) {
  const Eigen::Vector3d up = pose.linear().col(2);
  Eigen::Vector2d along = pose.linear().col(0).head<2>();  // standing: the way it faces
  if (heading) along = *heading;
  if (along.norm() < 1e-9 || up.z() < 1e-3) return 0.0;
  return -up.head<2>().dot(along.normalized()) / up.z();
}

RouteGeometry routeGeometry(const Poses& poses) {
  const std::size_t n = poses.size();
  RouteGeometry g{std::vector<double>(n, 0.0), std::vector<std::optional<Eigen::Vector2d>>(n),
                  std::vector<double>(n, 0.0), std::vector<double>(n, 1.0)};
  for (std::size_t k = 1; k < n; ++k)
    g.s[k] = g.s[k - 1] + (poses[k].translation() - poses[k - 1].translation()).head<2>().norm();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k > 0 ? k - 1 : 0;
    const std::size_t b = std::min(k + 1, n - 1);
    const Eigen::Vector2d d = (poses[b].translation() - poses[a].translation()).head<2>();
    if (g.s[b] - g.s[a] >= 0.05) g.heading[k] = d / d.norm();
    g.attitude_grade[k] = attitudeGrade(poses[k], g.heading[k]);
    if (g.heading[k] && g.heading[k]->dot(poses[k].linear().col(0).head<2>()) < 0.0)
      g.facing[k] = -1.0;
  }
  return g;
}

// A later pose j on a street an earlier pose i drove: (z_j + c_j) - (z_i + c_i) should be the
// earlier pass's rise to j along its direction, i.e. c_j - c_i = difference.
struct RevisitPair {
  std::size_t i;
  std::size_t j;
  double difference;
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
      const double rise = g.heading[i] ? g.attitude_grade[i] * offset.dot(*g.heading[i]) : 0.0;
      best = RevisitPair{i, j, poses[i].translation().z() + rise - poses[j].translation().z()};
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

double sampleAt(const std::vector<double>& u, double s) {
  const double x = std::clamp(s / kStep, 0.0, static_cast<double>(u.size() - 1));
  const auto a = static_cast<std::size_t>(std::floor(x));
  const std::size_t b = std::min(a + 1, u.size() - 1);
  return u[a] + (x - static_cast<double>(a)) * (u[b] - u[a]);
}

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

// Values given at the poses as a function of arc length, sampled every kStep metres.
std::vector<double> alongPath(const std::vector<double>& s, const std::vector<double>& value,
                              std::size_t m) {
  std::vector<double> u(m);
  std::size_t k = 0;
  for (std::size_t q = 0; q < m; ++q) {
    const double at = static_cast<double>(q) * kStep;
    while (k + 1 < s.size() && s[k + 1] < at) ++k;
    const std::size_t next = std::min(k + 1, s.size() - 1);
    const double span = s[next] - s[k];
    const double t = span > 0.0 ? std::clamp((at - s[k]) / span, 0.0, 1.0) : 0.0;
    u[q] = value[k] + t * (value[next] - value[k]);
  }
  return u;
}

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
  std::vector<double> z(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) z[k] = poses[k].translation().z();
  const std::vector<double> height = alongPath(g.s, z, m);
  const std::vector<double> attitude = alongPath(g.s, g.attitude_grade, m);
  const std::vector<double> facing = alongPath(g.s, g.facing, m);
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
    const auto at = [&](std::size_t k) {
      const double x = g.s[k] / kStep;
      const auto a = static_cast<Eigen::Index>(std::floor(x));
      return std::pair{a, x - static_cast<double>(a)};
    };
    const auto [i, ti] = at(r.i);
    const auto [j, tj] = at(r.j);
    equations.add({{j, 1.0 - tj}, {j + 1, tj}, {i, ti - 1.0}, {i + 1, -ti}}, r.difference, revisit);
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
    out.change[k] = sampleAt(u, g.s[k]) - sampleAt(u, 0.0);
    out.poses[k].translation().z() += out.change[k];
    out.max_change = std::max(out.max_change, std::abs(out.change[k]));
  }
  return out;
}

}  // namespace socc::sim
