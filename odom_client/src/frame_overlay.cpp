#include "socc/odom/frame_overlay.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "socc/chunk_features.hpp"

namespace socc::odom {

FrameSplit splitFrame(const LocalMap& map, const LabeledCloud& cloud,
                      const Eigen::Isometry3d& pose) {
  if (map.voxelSize() <= 0.0) throw std::logic_error("splitFrame: the map has no voxel grid");
  // One lookup per voxel of the frame, not per point. Points in map voxels without moments
  // (chunk::kMomentsBelow points or more: most of a dense sensor's near ones) change nothing
  // the client can follow, so they are not summed at all.
  std::vector<std::optional<std::size_t>> ids;  // of the kept voxels, in order; none: outside
  const auto keep = [&](const VoxelIndex& key) {
    const std::optional<LocalMap::Held> held = map.find(key);
    if (held && !held->moments) return false;
    ids.push_back(held ? std::optional(held->id) : std::nullopt);
    return true;
  };
  std::vector<CloudVoxel> voxels = cloudVoxels(cloud, pose, map.voxelSize(), keep);
  FrameSplit out;
  const auto known = static_cast<std::size_t>(
      std::count_if(ids.begin(), ids.end(), [](const auto& id) { return id.has_value(); }));
  // Grown from empty, these vectors of large elements were copied into fresh memory at every
  // doubling: that took as long as the grouping itself.
  out.into_known.reserve(known);
  out.outside.reserve(voxels.size() - known);
  for (std::size_t k = 0; k < voxels.size(); ++k) {
    if (ids[k])
      out.into_known.emplace_back(*ids[k], voxels[k].moments);
    else
      out.outside.push_back(std::move(voxels[k]));
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
  for (std::size_t k = 0; k < merged.size(); ++k) {
    const std::size_t id = split.into_known[k].first;
    if (id < chunk_size)
      updated.set(id, std::move(merged[k]));
    else
      overlay[id - chunk_size] = std::move(merged[k]);
  }
  // The new voxels' features too (all of them in the first frame's: ten thousand and more).
  const std::size_t first_added = overlay.size();
  overlay.resize(first_added + split.outside.size());
  tbb::parallel_for(std::size_t{0}, split.outside.size(), [&](std::size_t k) {
    MapVoxel& v = overlay[first_added + k];
    v = toMapVoxel(split.outside[k], EigenSolver::kClosedForm);  // as the server's chunk has it
    v.occupancy = base.hitOccupancy();
  });
}

}  // namespace socc::odom
