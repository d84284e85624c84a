#include "socc/sim/path_proximity.hpp"

#include <algorithm>
#include <cmath>

namespace socc::sim {

PathProximity::PathProximity(const Path& path, double cell_size) : path_(path), cells_(cell_size) {
  const auto& pts = path_.points();
  for (std::size_t i = 0; i < pts.size(); ++i)
    cells_.add(pts[i].position.head<2>(), static_cast<std::uint32_t>(i));
}

bool PathProximity::near(const Eigen::Vector2d& xy, double radius) const {
  return search(xy, radius, nullptr, 0.0);
}

bool PathProximity::nearOtherPart(const Eigen::Vector2d& xy, double radius, double s,
                                  double window) const {
  return search(xy, radius, &s, window);
}

bool PathProximity::search(const Eigen::Vector2d& xy, double radius, const double* s,
                           double window) const {
  const auto& pts = path_.points();
  const double len = path_.length();
  return cells_.visitNear(xy, radius, [&](std::uint32_t i) {
    if ((pts[i].position.head<2>() - xy).squaredNorm() > radius * radius) return false;
    if (!s) return true;
    double ds = std::abs(pts[i].s - *s);
    if (path_.closed()) ds = std::min(ds, len - ds);
    return ds >= window;
  });
}

}  // namespace socc::sim
