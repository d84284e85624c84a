#pragma once
// Exact voxel traversal of a segment (Amanatides & Woo, 1987).
#include <Eigen/Core>
#include <vector>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

inline VoxelIndex voxelIndex(const Eigen::Vector3d& p, double inv_voxel_size) {
  return (p * inv_voxel_size).array().floor().cast<int>();
}

/// Appends every voxel the segment [from, to] passes through, in order, from the voxel of
/// `from` up to and including the voxel of `to`. Consecutive voxels share a face, and the
/// walk always ends exactly in to's voxel (step counts are fixed per axis, so rounding can
/// never overshoot).
void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out);

}  // namespace socc::map
