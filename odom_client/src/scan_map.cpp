#include "socc/odom/scan_map.hpp"

#include <tsl/robin_map.h>

#include <optional>

#include "socc/chunk_features.hpp"
#include "socc/recent_lookups.hpp"

namespace socc::odom {

std::vector<CloudVoxel> cloudVoxels(const LabeledCloud& cloud, const Eigen::Isometry3d& pose,
                                    double voxel_size, const KeepVoxel& keep) {
  constexpr std::uint32_t kLeftOut = ~std::uint32_t{0};
  const double inv_size = 1.0 / voxel_size;
  tsl::robin_map<VoxelIndex, std::uint32_t, VoxelIndexHash> slot_of;
  std::vector<CloudVoxel> voxels;
  // A LiDAR scan has a voxel for every few points. Grown from empty, both are copied into fresh
  // memory a dozen times, a few MB the last times (page faults). The vector's reserved pages
  // that are never written are never touched.
  slot_of.reserve(cloud.size() / 4);
  voxels.reserve(cloud.size() / 4);
  // A scan's consecutive points mostly share a voxel: its slot is reused without a lookup.
  std::optional<VoxelIndex> last_key;
  std::uint32_t last = kLeftOut;
  RecentLookups<VoxelIndex, std::uint32_t, VoxelIndexHash> recent;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p =
        (pose * cloud.points[i].cast<double>()).cast<float>().cast<double>();  // as transformed()
    if (!p.allFinite()) continue;
    const VoxelIndex key = voxelIndex(p, inv_size);
    if (!last_key || key != *last_key) {
      last_key = key;
      if (const std::uint32_t* slot = recent.find(key)) {
        last = *slot;
      } else {
        const auto [it, inserted] = slot_of.try_emplace(key, kLeftOut);
        if (inserted && (!keep || keep(key))) {
          it.value() = static_cast<std::uint32_t>(voxels.size());
          voxels.push_back(CloudVoxel{key, {}, {}});
        }
        last = it->second;
        recent.remember(key, last);
      }
    }
    if (last == kLeftOut) continue;
    CloudVoxel& v = voxels[last];
    v.moments.add(p);
    const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : 0;
    if (isValidClass(label)) ++v.labels[label];
  }
  return voxels;
}

MapVoxel toMapVoxel(const CloudVoxel& voxel, EigenSolver solver) {
  const PointMoments& m = voxel.moments;
  MapVoxel v;
  v.point = m.first;
  v.normal.setZero();
  v.occupancy = 1.f;
  const VoxelFeatures f = voxelFeatures(sampleCovariance(m.m2(), m.count), m.count, solver);
  if (f.valid) {
    v.normal = f.normal;
    v.planarity = static_cast<float>(f.planarity);
  }
  if (m.count < chunk::kMomentsBelow) {  // as a chunk would send the voxel
    v.moments.emplace();
    mergeMoments(*v.moments, m);
  }
  int best = 0;
  for (int c = 1; c < kNumClasses; ++c)
    if (voxel.labels[c] > voxel.labels[best]) best = c;
  v.label = static_cast<std::uint8_t>(best);
  v.label_prob = static_cast<float>(voxel.labels[best]) / static_cast<float>(m.count);
  return v;
}

std::vector<CloudVoxel> mergedVoxels(const std::vector<const std::vector<CloudVoxel>*>& parts) {
  std::size_t most = 0;
  for (const std::vector<CloudVoxel>* part : parts) most += part->size();
  tsl::robin_map<VoxelIndex, std::uint32_t, VoxelIndexHash> slot_of;
  slot_of.reserve(most);
  std::vector<CloudVoxel> merged;
  merged.reserve(most);
  for (const std::vector<CloudVoxel>* part : parts) {
    for (const CloudVoxel& v : *part) {
      const auto [it, inserted] =
          slot_of.try_emplace(v.key, static_cast<std::uint32_t>(merged.size()));
      if (inserted) {
        merged.push_back(v);
        continue;
      }
      CloudVoxel& m = merged[it->second];
      m.moments.add(v.moments);
      for (int c = 0; c < kNumClasses; ++c) m.labels[c] += v.labels[c];
    }
  }
  return merged;
}

namespace {

std::vector<MapVoxel> mapVoxels(const std::vector<CloudVoxel>& voxels) {
  std::vector<MapVoxel> out;
  out.reserve(voxels.size());
  for (const CloudVoxel& v : voxels)
    // Iterative: the start-up of a sparse sensor registers against this map, and the closed
    // form's noise in line-like voxels swung it by metres (test_closed_loop, office/vlp32).
    out.push_back(toMapVoxel(v, EigenSolver::kIterative));
  return out;
}

}  // namespace

LocalMap buildVoxelMap(const std::vector<CloudVoxel>& voxels) {
  return LocalMap(mapVoxels(voxels));
}

std::vector<MapVoxel> scanVoxels(const LabeledCloud& cloud, double voxel_size) {
  return mapVoxels(cloudVoxels(cloud, Eigen::Isometry3d::Identity(), voxel_size));
}

LocalMap buildScanMap(const LabeledCloud& cloud, double voxel_size) {
  return LocalMap(scanVoxels(cloud, voxel_size));
}

}  // namespace socc::odom
