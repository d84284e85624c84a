#pragma once
// Axis-aligned voxel-index bounds of a metric region, safe for huge or tiny coordinates.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

inline int clampedFloor(double v) {
  constexpr double kLimit = 1.0e9;  // well inside int32; no map reaches it
  return static_cast<int>(std::floor(std::clamp(v, -kLimit, kLimit)));
}

struct IndexBox {
  VoxelIndex lo, hi;  // inclusive
  static IndexBox of(const Eigen::Vector3d& min, const Eigen::Vector3d& max, double voxel_size) {
    IndexBox b;
    for (int i = 0; i < 3; ++i) {
      b.lo[i] = clampedFloor(min[i] / voxel_size);
      b.hi[i] = clampedFloor(max[i] / voxel_size);
    }
    return b;
  }
  BlockKey blockLo() const { return blockOf(lo); }
  BlockKey blockHi() const { return blockOf(hi); }
};

}  // namespace socc::map
