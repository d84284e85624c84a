#include "socc/odom/frame_overlay.hpp"

#include <tbb/parallel_for.h>
#include <tsl/robin_map.h>

#include <optional>
#include <stdexcept>

#include "socc/chunk_features.hpp"
#include "socc/labels.hpp"

namespace socc::odom {

FrameSplit splitFrame(const LocalMap& map, const LabeledCloud& cloud,
                      const Eigen::Isometry3d& pose) {
  if (map.voxelSize() <= 0.0) throw std::logic_error("splitFrame: the map has no voxel grid");
  const double inv_size = 1.0 / map.voxelSize();
  FrameSplit out;
  // Where each voxel of the frame goes: an entry of outside, of into_known, or nowhere (a voxel
  // of many points). The map is asked once per voxel, and a scan's consecutive points mostly
  // share a voxel, whose answer is reused without a lookup.
  enum class To : std::uint8_t { kOutside, kKnown, kNowhere };
  struct Slot {
    To to;
    std::uint32_t index;
  };
  tsl::robin_map<VoxelIndex, Slot, VoxelIndexHash> slot_of;
  VoxelIndex last_key(0, 0, 0);
  std::optional<Slot> last;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p =
        (pose * cloud.points[i].cast<double>()).cast<float>().cast<double>();  // as sent
    if (!p.allFinite()) continue;
    const VoxelIndex key = voxelIndex(p, inv_size);
    if (!last || key != last_key) {
      auto it = slot_of.find(key);
      if (it == slot_of.end()) {
        Slot slot{To::kNowhere, 0};
        if (const std::optional<LocalMap::Held> held = map.find(key); !held) {
          slot = {To::kOutside, static_cast<std::uint32_t>(out.outside.size())};
          out.outside.push_back(CloudVoxel{key, {}, {}});
        } else if (held->moments) {
          slot = {To::kKnown, static_cast<std::uint32_t>(out.into_known.size())};
          out.into_known.emplace_back(held->id, PointMoments{});
        }
        it = slot_of.emplace(key, slot).first;
      }
      last = it->second;
      last_key = key;
    }
    if (last->to == To::kKnown) {
      out.into_known[last->index].second.add(p);
    } else if (last->to == To::kOutside) {
      CloudVoxel& v = out.outside[last->index];
      v.moments.add(p);
      const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : 0;
      if (isValidClass(label)) ++v.labels[label];
    }
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
