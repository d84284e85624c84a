#include "socc/map/voxel_features.hpp"

#include <Eigen/Eigenvalues>

namespace socc::map {

VoxelFeatures computeFeatures(const VoxelStats& stats) {
  VoxelFeatures f;
  if (stats.count < kMinPointsForFeatures) return f;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(stats.covariance());  // closed form: fast and exact enough for 3x3
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = l.sum();
  f.normal = solver.eigenvectors().col(0);
  // Deterministic sign: normal points to +z (or +y / +x when horizontal).
  const int major = f.normal.z() != 0.0 ? 2 : (f.normal.y() != 0.0 ? 1 : 0);
  if (f.normal[major] < 0.0) f.normal = -f.normal;
  f.planarity = sum > 0.0 ? l[0] / sum : 0.0;
  f.valid = true;
  return f;
}

}  // namespace socc::map
