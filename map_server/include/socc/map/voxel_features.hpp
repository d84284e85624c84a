#pragma once
// Registration features of a voxel derived from its covariance (paper, Sec. SOCC-ICP).
#include <Eigen/Core>

#include "socc/map/semantic_voxel.hpp"

namespace socc::map {

inline constexpr std::uint32_t kMinPointsForFeatures = 5;

struct VoxelFeatures {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // eigenvector of the smallest eigenvalue
  double planarity = -1.0;                           // tau = l3 / (l1 + l2 + l3)
  bool valid = false;                                // false below kMinPointsForFeatures points
};

VoxelFeatures computeFeatures(const VoxelStats& stats);

}  // namespace socc::map
