#pragma once
// Exact voxel traversal of a segment (Amanatides & Woo, 1987).
#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

/// Calls visit(voxel) for every voxel the segment [from, to] passes through, in order, from
/// the voxel of `from` up to and including the voxel of `to`. Consecutive voxels share a
/// face, and the walk always ends exactly in to's voxel (step counts are fixed per axis, so
/// rounding can never overshoot). A template so the integrator's hot loop inlines visit.
template <typename Visit>
void forEachVoxelOnRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                       Visit&& visit) {
  const double inv = 1.0 / voxel_size;
  const Eigen::Vector3d a = from * inv;  // in voxel units
  const Eigen::Vector3d b = to * inv;
  const VoxelIndex start = a.array().floor().cast<int>();
  const VoxelIndex end = b.array().floor().cast<int>();
  const Eigen::Vector3d d = b - a;

  int step[3];
  double t_max[3];
  double t_delta[3];
  int total = 0;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    step[i] = end[i] > start[i] ? 1 : (end[i] < start[i] ? -1 : 0);
    total += std::abs(end[i] - start[i]);
    if (step[i] == 0) {  // this axis never moves (also covers d[i] == 0)
      t_max[i] = kInf;
      t_delta[i] = kInf;
      continue;
    }
    const double boundary = step[i] > 0 ? start[i] + 1.0 : static_cast<double>(start[i]);
    t_max[i] = (boundary - a[i]) / d[i];
    t_delta[i] = 1.0 / std::abs(d[i]);
  }

  // The walk takes exactly |end - start|_1 steps; an axis that reached its end index gets
  // t_max = inf, so rounding can never make it overshoot. Scalars and selects instead of
  // arrays indexed by the axis: the loop stays in registers and has no data-dependent
  // branches (the axis choice is unpredictable), which makes it several times faster.
  int x = start.x(), y = start.y(), z = start.z();
  double tx = t_max[0], ty = t_max[1], tz = t_max[2];
  const double dx = t_delta[0], dy = t_delta[1], dz = t_delta[2];
  const int sx = step[0], sy = step[1], sz = step[2];
  const int ex = end.x(), ey = end.y(), ez = end.z();
  visit(static_cast<const VoxelIndex&>(start));
  for (int k = 0; k < total; ++k) {
    // Bitwise & and |, not && and ||: no short-circuit branches.
    const bool mx = (tx < ty) & (tx < tz);
    const bool my = !mx & (ty < tz);
    const bool mz = !(mx | my);
    x += mx ? sx : 0;
    y += my ? sy : 0;
    z += mz ? sz : 0;
    tx += mx ? dx : 0.0;
    ty += my ? dy : 0.0;
    tz += mz ? dz : 0.0;
    tx = (x == ex) ? kInf : tx;
    ty = (y == ey) ? kInf : ty;
    tz = (z == ez) ? kInf : tz;
    visit(VoxelIndex(x, y, z));
  }
}

/// Appends every voxel of forEachVoxelOnRay(from, to) to out.
void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out);

}  // namespace socc::map
