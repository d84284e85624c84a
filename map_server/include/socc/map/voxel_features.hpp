#pragma once
// Registration features of a map voxel: socc/voxel.hpp's, from the voxel's statistics.
#include "socc/map/semantic_voxel.hpp"
#include "socc/voxel.hpp"

namespace socc::map {

inline VoxelFeatures computeFeatures(const VoxelStats& stats) {
  return voxelFeatures(stats.covariance(), stats.count);
}

}  // namespace socc::map
