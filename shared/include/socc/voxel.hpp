#pragma once
// What a voxel is on both sides: its integer key, the key's hash, and the point statistics
// (moments) a voxel's normal and planarity come from. The map server's grid and the odometry
// client's scan maps and downsampling use these, so a voxel of one scan and a voxel of the
// map agree on where they are and on their geometry (paper, Sec. SOCC-ICP).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>

namespace socc {

/// Integer voxel coordinate: floor(p / voxel_size) per axis.
using VoxelIndex = Eigen::Vector3i;

/// The voxel holding p. Takes the inverse size: one multiplication per axis in hot loops, and
/// every caller rounds the same way.
inline VoxelIndex voxelIndex(const Eigen::Vector3d& p, double inv_voxel_size) {
  return (p * inv_voxel_size).array().floor().cast<int>();
}

/// Spatial hash of a voxel (or block) index.
struct VoxelIndexHash {
  std::size_t operator()(const Eigen::Vector3i& k) const noexcept {
    // Large primes (Teschner et al.): cheap and spreads neighbouring voxels well.
    return (static_cast<std::size_t>(static_cast<std::uint32_t>(k.x())) * 73856093u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k.y())) * 19349669u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k.z())) * 83492791u);
  }
};

/// Lexicographic order of indices: used wherever output order must not depend on hashing.
inline bool indexLess(const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

/// Points a voxel needs before its covariance says anything about the surface: below this its
/// normal and planarity are unknown.
inline constexpr std::uint32_t kMinPointsForFeatures = 5;

/// Count, first point and sums of the points of a voxel, taken relative to the first point
/// (shifted data: no cancellation within a voxel even far from the origin, and no division
/// per point as in Welford's update).
struct PointMoments {
  std::uint32_t count = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   // the first point added
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();     // sum of (p - first)
  Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();  // sum of (p - first)(p - first)^T

  void add(const Eigen::Vector3d& p) {
    if (count == 0) first = p;
    ++count;
    const Eigen::Vector3d d = p - first;
    sum += d;
    sum_sq.noalias() += d * d.transpose();
  }
  /// Adds the points of other (as if added one by one after these, up to rounding).
  void add(const PointMoments& other) {
    if (other.count == 0) return;
    if (count == 0) {
      *this = other;
      return;
    }
    const Eigen::Vector3d d = other.first - first;  // other's points are d + their deviations
    const double n = other.count;
    sum_sq.noalias() += other.sum_sq + d * other.sum.transpose() + other.sum * d.transpose();
    sum_sq.noalias() += n * d * d.transpose();
    sum += other.sum + n * d;
    count += other.count;
  }
  Eigen::Vector3d mean() const { return first + sum / static_cast<double>(count); }
  /// Sum of squared deviations from the mean.
  Eigen::Matrix3d m2() const { return sum_sq - sum * sum.transpose() / static_cast<double>(count); }
};

/// A voxel's point moments as a map keeps them: count, mean and the sum of squared deviations
/// from the mean (xx xy xz yy yz zz), in floats.
struct StoredMoments {
  std::uint32_t count = 0;
  std::array<float, 3> mean{};
  std::array<float, 6> m2{};
};

/// The symmetric matrix of stored upper-triangle components xx xy xz yy yz zz.
Eigen::Matrix3d symmetricOf(const std::array<float, 6>& upper);

/// Merges a scan's points in a voxel into its stored moments (Chan et al.'s parallel update, in
/// double). The map server's voxel update and a client's stand-in for it (its pipelined target)
/// both use it, so the two agree.
void mergeMoments(std::uint32_t& count, std::array<float, 3>& mean, std::array<float, 6>& m2,
                  const PointMoments& frame);
inline void mergeMoments(StoredMoments& m, const PointMoments& frame) {
  mergeMoments(m.count, m.mean, m.m2, frame);
}

/// Sample covariance M2 / (n - 1); zero below two points.
inline Eigen::Matrix3d sampleCovariance(const Eigen::Matrix3d& m2, std::uint32_t count) {
  if (count < 2) return Eigen::Matrix3d::Zero();
  return m2 * (1.0 / static_cast<double>(count - 1));
}

/// Registration features of a voxel derived from its covariance.
struct VoxelFeatures {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();       // eigenvector of the smallest eigenvalue
  double planarity = -1.0;                                // tau = l3 / (l1 + l2 + l3)
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  // ascending: l3 <= l2 <= l1
  bool valid = false;  // false below kMinPointsForFeatures points
};

/// How voxelFeatures decomposes the covariance. The closed form is several times faster (the
/// map server computes features for every voxel of every chunk); the iterative QR solver is
/// accurate where eigenvalues nearly coincide, e.g. the undefined normal of a line-like voxel
/// (points of one ring), which the closed form returns as rounding noise.
enum class EigenSolver { kClosedForm, kIterative };

/// Normal (unit, sign fixed: +z, or +y / +x when horizontal, so equal voxels give equal
/// normals) and planarity of a voxel of count points with this covariance; invalid below
/// kMinPointsForFeatures points.
VoxelFeatures voxelFeatures(const Eigen::Matrix3d& covariance, std::uint32_t count,
                            EigenSolver solver = EigenSolver::kClosedForm);

}  // namespace socc
