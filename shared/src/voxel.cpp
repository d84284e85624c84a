#include "socc/voxel.hpp"

#include <Eigen/Eigenvalues>

namespace socc {

Eigen::Matrix3d symmetricOf(const std::array<float, 6>& upper) {
  Eigen::Matrix3d m;
  m << upper[0], upper[1], upper[2],  //
      upper[1], upper[3], upper[4],   //
      upper[2], upper[4], upper[5];
  return m;
}

void mergeMoments(std::uint32_t& count, std::array<float, 3>& mean, std::array<float, 6>& m2,
                  const PointMoments& frame) {
  if (frame.count == 0) return;
  const Eigen::Vector3d mean_b = frame.mean();
  const Eigen::Matrix3d mb = frame.m2();
  if (count == 0) {
    for (int i = 0; i < 3; ++i) mean[i] = static_cast<float>(mean_b[i]);
    m2 = {static_cast<float>(mb(0, 0)), static_cast<float>(mb(0, 1)), static_cast<float>(mb(0, 2)),
          static_cast<float>(mb(1, 1)), static_cast<float>(mb(1, 2)), static_cast<float>(mb(2, 2))};
    count = frame.count;
    return;
  }
  const double na = count;
  const double nb = frame.count;
  const double n = na + nb;
  const Eigen::Vector3d mean_a(mean[0], mean[1], mean[2]);
  const Eigen::Vector3d delta = mean_b - mean_a;
  const Eigen::Vector3d merged = mean_a + delta * (nb / n);
  const Eigen::Matrix3d corr = delta * delta.transpose() * (na * nb / n);
  const int idx[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int k = 0; k < 6; ++k) {
    const int r = idx[k][0], c = idx[k][1];
    m2[k] = static_cast<float>(m2[k] + mb(r, c) + corr(r, c));
  }
  for (int i = 0; i < 3; ++i) mean[i] = static_cast<float>(merged[i]);
  count += frame.count;
}

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
