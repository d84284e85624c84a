#include "socc/odom/frame_overlay.hpp"

#include <tbb/parallel_for.h>

#include <optional>
#include <stdexcept>

#include "socc/chunk_features.hpp"

namespace socc::odom {

FrameSplit splitFrame(const LocalMap& map, const LabeledCloud& cloud,
                      const Eigen::Isometry3d& pose) {
  if (map.voxelSize() <= 0.0) throw std::logic_error("splitFrame: the map has no voxel grid");
  // One lookup per voxel of the frame, not per point.
  FrameSplit out;
  for (CloudVoxel& v : cloudVoxels(cloud, pose, map.voxelSize())) {
    const std::optional<LocalMap::Held> held = map.find(v.key);
    if (!held)
      out.outside.push_back(std::move(v));
    else if (held->moments)
      out.into_known.emplace_back(held->id, v.moments);
  }
  return out;
}

MapVoxel withPoints(MapVoxel v, const PointMoments& points) {
  if (!v.moments) return v;  // e.g. an update that reached kMomentsBelow points
  StoredMoments& m = *v.moments;
  mergeMoments(m, points);
  const VoxelFeatures f = voxelFeatures(sampleCovariance(symmetricOf(m.m2), m.count), m.count);
  if (f.valid) {
    v.normal = f.normal;
    v.planarity = static_cast<float>(f.planarity);
  }
  if (m.count >= chunk::kMomentsBelow) v.moments.reset();
  return v;
}

void addFrame(const LocalMap& base, std::size_t chunk_size, const LabeledCloud& cloud,
              const Eigen::Isometry3d& pose, std::vector<MapVoxel>& overlay,
              VoxelUpdates& updated) {
  const FrameSplit split = splitFrame(base, cloud, pose);
  // Each merge is independent (an eigen-decomposition each): in parallel.
  std::vector<MapVoxel> merged(split.into_known.size());
  tbb::parallel_for(std::size_t{0}, merged.size(), [&](std::size_t k) {
    const auto& [id, points] = split.into_known[k];
    merged[k] = withPoints(base.voxel(id), points);
  });
  updated.reserve(updated.size() + merged.size());
  for (std::size_t k = 0; k < merged.size(); ++k) {
    const std::size_t id = split.into_known[k].first;
    if (id < chunk_size)
      updated[id] = std::move(merged[k]);
    else
      overlay[id - chunk_size] = std::move(merged[k]);
  }
  for (const CloudVoxel& added : split.outside) {
    MapVoxel v = toMapVoxel(added);
    v.occupancy = base.hitOccupancy();
    overlay.push_back(std::move(v));
  }
}

}  // namespace socc::odom
