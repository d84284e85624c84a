#include "socc/odom/scan_map.hpp"

#include <tsl/robin_map.h>

#include <array>

#include "socc/labels.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {
namespace {

struct ScanVoxel {
  PointMoments moments;
  std::array<std::uint32_t, kNumClasses> labels{};
};

}  // namespace

std::vector<MapVoxel> scanVoxels(const LabeledCloud& cloud, double voxel_size) {
  const double inv_size = 1.0 / voxel_size;
  tsl::robin_map<VoxelIndex, ScanVoxel, VoxelIndexHash> grid;
  std::vector<VoxelIndex> order;  // insertion order: deterministic output
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.points[i].cast<double>();
    if (!p.allFinite()) continue;
    const VoxelIndex key = voxelIndex(p, inv_size);
    auto [it, inserted] = grid.try_emplace(key);
    if (inserted) order.push_back(key);
    ScanVoxel& s = it.value();
    s.moments.add(p);
    const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : 0;
    if (isValidClass(label)) ++s.labels[label];
  }

  std::vector<MapVoxel> voxels;
  voxels.reserve(order.size());
  for (const VoxelIndex& key : order) {
    const ScanVoxel& s = grid.at(key);
    MapVoxel v;
    v.point = s.moments.first;
    v.normal.setZero();
    v.occupancy = 1.f;
    const PointMoments& m = s.moments;
    // Iterative: the start-up of a sparse sensor registers against this map, and the closed
    // form's noise in line-like voxels swung it by metres (test_closed_loop, office/vlp32).
    const VoxelFeatures f =
        voxelFeatures(sampleCovariance(m.m2(), m.count), m.count, EigenSolver::kIterative);
    if (f.valid) {
      v.normal = f.normal;
      v.planarity = static_cast<float>(f.planarity);
    }
    int best = 0;
    for (int c = 1; c < kNumClasses; ++c)
      if (s.labels[c] > s.labels[best]) best = c;
    v.label = static_cast<std::uint8_t>(best);
    v.label_prob = static_cast<float>(s.labels[best]) / static_cast<float>(m.count);
    voxels.push_back(v);
  }
  return voxels;
}

LocalMap buildScanMap(const LabeledCloud& cloud, double voxel_size) {
  return LocalMap(scanVoxels(cloud, voxel_size));
}

}  // namespace socc::odom
