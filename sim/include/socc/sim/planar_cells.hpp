#pragma once
// Indices of points in the plane, bucketed in square cells: the candidates for "which points lie
// within r of here" (the caller measures the distance, it knows the points).
#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace socc::sim {

class PlanarCells {
 public:
  explicit PlanarCells(double cell_size) : cell_size_(cell_size) {}

  void add(const Eigen::Vector2d& xy, std::uint32_t index) {
    cells_[key(cell(xy.x()), cell(xy.y()))].push_back(index);
  }

  /// visit(index) for every point in the cells that a disc of radius around xy touches (a
  /// superset of the points within radius); stops early when visit returns true.
  template <typename Visit>
  bool visitNear(const Eigen::Vector2d& xy, double radius, Visit&& visit) const {
    for (std::int64_t ix = cell(xy.x() - radius); ix <= cell(xy.x() + radius); ++ix)
      for (std::int64_t iy = cell(xy.y() - radius); iy <= cell(xy.y() + radius); ++iy) {
        const auto it = cells_.find(key(ix, iy));
        if (it == cells_.end()) continue;
        for (const std::uint32_t i : it->second)
          if (visit(i)) return true;
      }
    return false;
  }

 private:
  std::int64_t cell(double v) const {
    return static_cast<std::int64_t>(std::floor(v / cell_size_));
  }
  static std::int64_t key(std::int64_t ix, std::int64_t iy) {
    const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix));
    return static_cast<std::int64_t>((hi << 32) | static_cast<std::uint32_t>(iy));
  }

  double cell_size_;
  tsl::robin_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace socc::sim
