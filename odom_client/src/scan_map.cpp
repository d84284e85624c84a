#include "socc/odom/scan_map.hpp"

#include <tsl/robin_map.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

#include "socc/labels.hpp"

namespace socc::odom {
namespace {

struct Key {
  std::int32_t x, y, z;
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
  std::size_t operator()(const Key& k) const {
    return (static_cast<std::size_t>(k.x) * 73856093u) ^
           (static_cast<std::size_t>(k.y) * 19349669u) ^
           (static_cast<std::size_t>(k.z) * 83492791u);
  }
};

struct Stats {
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
  int count = 0;
  std::array<int, kNumClasses> labels{};
};

}  // namespace

LocalMap buildScanMap(const LabeledCloud& cloud, double voxel_size) {
  tsl::robin_map<Key, Stats, KeyHash> grid;
  std::vector<Key> order;  // insertion order: deterministic output
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.points[i].cast<double>();
    if (!p.allFinite()) continue;
    const Eigen::Vector3d v = (p / voxel_size).array().floor();
    const Key key{static_cast<std::int32_t>(v.x()), static_cast<std::int32_t>(v.y()),
                  static_cast<std::int32_t>(v.z())};
    auto [it, inserted] = grid.try_emplace(key);
    Stats& s = it.value();
    if (inserted) {
      s.first = p;
      order.push_back(key);
    }
    s.sum += p;
    s.sum_sq += p * p.transpose();
    ++s.count;
    const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : 0;
    if (isValidClass(label)) ++s.labels[label];
  }

  std::vector<MapVoxel> voxels;
  voxels.reserve(order.size());
  for (const Key& key : order) {
    const Stats& s = grid.at(key);
    MapVoxel v;
    v.point = s.first;
    v.normal.setZero();
    v.occupancy = 1.f;
    if (s.count >= 5) {
      const Eigen::Vector3d mean = s.sum / s.count;
      const Eigen::Matrix3d cov = s.sum_sq / s.count - mean * mean.transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // ascending eigenvalues
      const double total = eig.eigenvalues().sum();
      v.planarity =
          total > 0.0 ? static_cast<float>(std::max(0.0, eig.eigenvalues()[0]) / total) : 0.f;
      v.normal = eig.eigenvectors().col(0).normalized();
    }
    int best = 0;
    for (int c = 1; c < kNumClasses; ++c)
      if (s.labels[c] > s.labels[best]) best = c;
    v.label = static_cast<std::uint8_t>(best);
    v.label_prob = static_cast<float>(s.labels[best]) / s.count;
    voxels.push_back(v);
  }
  return LocalMap(std::move(voxels));
}

}  // namespace socc::odom
