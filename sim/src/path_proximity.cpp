#include "socc/sim/path_proximity.hpp"

#include <cmath>

namespace socc::sim {

PathProximity::PathProximity(const Path& path, double cell_size)
    : path_(path), cell_size_(cell_size) {
  const auto& pts = path_.points();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int ix = static_cast<int>(std::floor(pts[i].position.x() / cell_size_));
    const int iy = static_cast<int>(std::floor(pts[i].position.y() / cell_size_));
    cells_[key(ix, iy)].push_back(static_cast<std::uint32_t>(i));
  }
}

std::int64_t PathProximity::key(int ix, int iy) const {
  const std::uint64_t hi = static_cast<std::uint32_t>(ix);
  return static_cast<std::int64_t>((hi << 32) | static_cast<std::uint32_t>(iy));
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
  const int x0 = static_cast<int>(std::floor((xy.x() - radius) / cell_size_));
  const int x1 = static_cast<int>(std::floor((xy.x() + radius) / cell_size_));
  const int y0 = static_cast<int>(std::floor((xy.y() - radius) / cell_size_));
  const int y1 = static_cast<int>(std::floor((xy.y() + radius) / cell_size_));
  for (int ix = x0; ix <= x1; ++ix) {
    for (int iy = y0; iy <= y1; ++iy) {
      const auto it = cells_.find(key(ix, iy));
      if (it == cells_.end()) continue;
      for (const std::uint32_t i : it->second) {
        if ((pts[i].position.head<2>() - xy).squaredNorm() > radius * radius) continue;
        if (s) {
          double ds = std::abs(pts[i].s - *s);
          if (path_.closed()) ds = std::min(ds, len - ds);
          if (ds < window) continue;
        }
        return true;
      }
    }
  }
  return false;
}

}  // namespace socc::sim
