#include "socc/voxel.hpp"

#include <Eigen/Eigenvalues>

namespace socc {

VoxelFeatures voxelFeatures(const Eigen::Matrix3d& covariance, std::uint32_t count,
                            EigenSolver solver_kind) {
  VoxelFeatures f;
  if (count < kMinPointsForFeatures) return f;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  if (solver_kind == EigenSolver::kClosedForm)
    solver.computeDirect(covariance);
  else
    solver.compute(covariance);
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = l.sum();
  f.normal = solver.eigenvectors().col(0);
  const int major = f.normal.z() != 0.0 ? 2 : (f.normal.y() != 0.0 ? 1 : 0);
  if (f.normal[major] < 0.0) f.normal = -f.normal;
  f.planarity = sum > 0.0 ? l[0] / sum : 0.0;
  f.eigenvalues = l;
  f.valid = true;
  return f;
}

}  // namespace socc
