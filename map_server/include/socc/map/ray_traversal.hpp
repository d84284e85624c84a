#pragma once
// Exact voxel traversal of a segment (Amanatides & Woo, 1987).
#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

/// The state of one segment's walk, in voxel units: the current voxel, the end voxel, and per
/// axis the step (-1, 0, 1), the ray parameter t in [0, 1] of the next boundary crossing
/// (inf: the axis never moves) and the parameter between two crossings.
struct RayWalk {
  int x, y, z;
  int ex, ey, ez;
  int sx, sy, sz;
  double tx, ty, tz;
  double dx, dy, dz;
  int steps;  // steps left: |end - current|_1

  /// Steps from the start during which no axis can have passed its end voxel, so the walk
  /// needs no end check (markRays' lanes): the crossings they take lie at t < 1 - 1e-6 (up
  /// to rounding), while an axis past its end would next cross at t >= 1 (up to rounding,
  /// ~1e-13 here), so it is never the smallest. A segment that ends at a voxel centre has
  /// its last crossing half a voxel before the end: all its steps are unchecked.
  int uncheckedSteps() const;
};

/// One axis of a walk from a to a + d (voxel units; voxels start and end): the step, the
/// parameter of the first boundary crossing and the parameter between crossings.
inline void startRayAxis(double a, double d, int start, int end, int& step, double& t,
                         double& delta) {
  step = end > start ? 1 : (end < start ? -1 : 0);
  if (step == 0) {  // this axis never moves (also covers d == 0)
    t = std::numeric_limits<double>::infinity();
    delta = std::numeric_limits<double>::infinity();
    return;
  }
  const double boundary = step > 0 ? start + 1.0 : static_cast<double>(start);
  t = (boundary - a) / d;
  delta = 1.0 / std::abs(d);
}

/// Starts the walk to `to` from a (= from / voxel size, in voxel `start`); inv: 1 / voxel
/// size. Walks from one origin share a and start.
inline RayWalk startRayWalk(const Eigen::Vector3d& a, const VoxelIndex& start,
                            const Eigen::Vector3d& to, double inv) {
  const Eigen::Vector3d b = to * inv;
  const VoxelIndex end(floorToInt(b.x()), floorToInt(b.y()), floorToInt(b.z()));
  const Eigen::Vector3d d = b - a;
  RayWalk w;
  w.x = start.x();
  w.y = start.y();
  w.z = start.z();
  w.ex = end.x();
  w.ey = end.y();
  w.ez = end.z();
  startRayAxis(a.x(), d.x(), start.x(), end.x(), w.sx, w.tx, w.dx);
  startRayAxis(a.y(), d.y(), start.y(), end.y(), w.sy, w.ty, w.dy);
  startRayAxis(a.z(), d.z(), start.z(), end.z(), w.sz, w.tz, w.dz);
  w.steps =
      std::abs(end.x() - start.x()) + std::abs(end.y() - start.y()) + std::abs(end.z() - start.z());
  return w;
}

/// Starts the walk from `from` to `to`: forEachVoxelOnRay is startRayWalk + continueRayWalk.
inline RayWalk startRayWalk(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                            double voxel_size) {
  const double inv = 1.0 / voxel_size;
  const Eigen::Vector3d a = from * inv;  // in voxel units
  const VoxelIndex start(floorToInt(a.x()), floorToInt(a.y()), floorToInt(a.z()));
  return startRayWalk(a, start, to, inv);
}

inline int RayWalk::uncheckedSteps() const {
  constexpr double kSafeT = 1.0 - 1e-6;
  const auto axis = [](double t, double delta, int n) {
    if (n == 0) return 0;
    // Crossings at t, t + delta, ... below kSafeT.
    const double below = std::ceil((kSafeT - t) / delta);
    return below <= 0.0 ? 0 : (below >= n ? n : static_cast<int>(below));
  };
  return axis(tx, dx, std::abs(ex - x)) + axis(ty, dy, std::abs(ey - y)) +
         axis(tz, dz, std::abs(ez - z));
}

/// Walks the remaining steps of w, calling visit(voxel) after each (w is left unchanged).
/// An axis that reached its end index gets t = inf, so rounding can never make it overshoot.
template <typename Visit>
void continueRayWalk(const RayWalk& w, Visit&& visit) {
  // Scalars and selects instead of arrays indexed by the axis: the loop stays in registers
  // and has few data-dependent branches.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int x = w.x, y = w.y, z = w.z;
  double tx = x == w.ex ? kInf : w.tx, ty = y == w.ey ? kInf : w.ty, tz = z == w.ez ? kInf : w.tz;
  const double dx = w.dx, dy = w.dy, dz = w.dz;
  const int sx = w.sx, sy = w.sy, sz = w.sz;
  const int ex = w.ex, ey = w.ey, ez = w.ez;
  for (int k = 0; k < w.steps; ++k) {
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

/// Calls visit(voxel) for every voxel the segment [from, to] passes through, in order, from
/// the voxel of `from` up to and including the voxel of `to`. Consecutive voxels share a
/// face, and the walk always ends exactly in to's voxel (step counts are fixed per axis, so
/// rounding can never overshoot). A template so the integrator's hot loop inlines visit.
template <typename Visit>
void forEachVoxelOnRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                       Visit&& visit) {
  const RayWalk w = startRayWalk(from, to, voxel_size);
  visit(VoxelIndex(w.x, w.y, w.z));
  continueRayWalk(w, visit);
}

/// Appends every voxel of forEachVoxelOnRay(from, to) to out.
void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out);

}  // namespace socc::map
