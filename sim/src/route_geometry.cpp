#include "route_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace socc::sim {
namespace {

double attitudeGrade(const Eigen::Isometry3d& pose, const std::optional<Eigen::Vector2d>& heading) {
  const Eigen::Vector3d up = pose.linear().col(2);
  Eigen::Vector2d along = pose.linear().col(0).head<2>();  // standing: the way it faces
  if (heading) along = *heading;
  if (along.norm() < 1e-9 || up.z() < 1e-3) return 0.0;
  return -up.head<2>().dot(along.normalized()) / up.z();
}

}  // namespace

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

std::vector<double> heightsOf(const Poses& poses) {
  std::vector<double> z(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) z[k] = poses[k].translation().z();
  return z;
}

std::vector<double> alongPath(const std::vector<double>& s, const std::vector<double>& value,
                              double step, std::size_t m) {
  std::vector<double> u(m);
  std::size_t k = 0;
  for (std::size_t q = 0; q < m; ++q) {
    const double at = static_cast<double>(q) * step;
    while (k + 1 < s.size() && s[k + 1] < at) ++k;
    const std::size_t next = std::min(k + 1, s.size() - 1);
    const double span = s[next] - s[k];
    const double t = span > 0.0 ? std::clamp((at - s[k]) / span, 0.0, 1.0) : 0.0;
    u[q] = value[k] + t * (value[next] - value[k]);
  }
  return u;
}

SampleBracket bracketOf(std::size_t size, double step, double s) {
  const double x = std::clamp(s / step, 0.0, static_cast<double>(size - 1));
  const std::size_t before = std::min(static_cast<std::size_t>(std::floor(x)), size - 2);
  return {before, x - static_cast<double>(before)};
}

double sampleAt(const std::vector<double>& u, double step, double s) {
  const auto [a, t] = bracketOf(u.size(), step, s);
  return u[a] + t * (u[a + 1] - u[a]);
}

}  // namespace socc::sim
