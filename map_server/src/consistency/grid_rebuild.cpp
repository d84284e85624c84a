#include "grid_rebuild.hpp"

#include <algorithm>
#include <optional>

namespace socc::consistency {

namespace {

/// The scan's cloud when the map takes it at pose.
std::optional<LabeledCloud> acceptedCloud(const map::SemanticOccupancyMap& map,
                                          const Eigen::Isometry3d& pose, const KeyframeScan& scan) {
  if (scan.empty()) return std::nullopt;
  LabeledCloud cloud = scan.cloud();
  if (!map.validate(pose, cloud).empty()) return std::nullopt;
  return cloud;
}

/// Integrates the keyframe's scan whole at its grid_pose, listing its footprint.
bool integrateWhole(map::SemanticOccupancyMap& map, Keyframe& k) {
  const std::optional<LabeledCloud> cloud = acceptedCloud(map, k.grid_pose, k.scan);
  k.footprint.clear();
  k.footprint_pose = k.grid_pose;
  if (cloud) map.integrate(k.grid_pose, *cloud, k.footprint);
  return cloud.has_value();
}

/// Integrates the keyframe's scan whole at its grid_pose, keeping no footprint (no region
/// rebuild will ask for it).
bool integrateUnlisted(map::SemanticOccupancyMap& map, Keyframe& k) {
  k.footprint = {};
  k.footprint_pose.reset();
  return integrateScan(map, k.grid_pose, k.scan);
}

/// The keyframes of [0, in_grid) that moved more than min_shift from their grid_pose.
std::vector<std::size_t> movedKeyframes(const std::vector<Keyframe>& keyframes, std::size_t in_grid,
                                        const std::vector<Eigen::Isometry3d>& estimates,
                                        double min_shift, double lever) {
  std::vector<std::size_t> moved;
  for (std::size_t i = 0; i < in_grid; ++i) {
    const Keyframe& k = keyframes[i];
    const Eigen::Isometry3d& estimate = estimates[static_cast<std::size_t>(k.id)];
    if (!k.scan.empty() && poseShift(k.grid_pose, estimate, lever) > min_shift) moved.push_back(i);
  }
  return moved;
}

/// Marks the keyframes of [0, in_grid) not marked yet whose footprints reach into blocks;
/// returns how many are marked in all.
std::size_t markReaching(map::SemanticOccupancyMap& grid, std::vector<Keyframe>& keyframes,
                         std::size_t in_grid, const map::BlockRegion& blocks,
                         std::vector<bool>& reaches) {
  for (std::size_t i = 0; i < in_grid && !blocks.empty(); ++i)
    if (!reaches[i]) reaches[i] = blocks.intersects(gridFootprint(grid, keyframes[i]));
  return static_cast<std::size_t>(std::count(reaches.begin(), reaches.end(), true));
}

}  // namespace

bool integrateScan(map::SemanticOccupancyMap& map, const Eigen::Isometry3d& pose,
                   const KeyframeScan& scan, const map::BlockRegion* within) {
  const std::optional<LabeledCloud> cloud = acceptedCloud(map, pose, scan);
  if (cloud && within != nullptr)
    map.integrate(pose, *cloud, *within);
  else if (cloud)
    map.integrate(pose, *cloud);
  return cloud.has_value();
}

double poseShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double lever) {
  const double angle = Eigen::AngleAxisd(from.linear().transpose() * to.linear()).angle();
  return (to.translation() - from.translation()).norm() + angle * lever;
}

const std::vector<map::BlockKey>& gridFootprint(map::SemanticOccupancyMap& map, Keyframe& k) {
  if (!k.footprint_pose || k.footprint_pose->matrix() != k.grid_pose.matrix()) {
    const std::optional<LabeledCloud> cloud = acceptedCloud(map, k.grid_pose, k.scan);
    k.footprint = cloud ? map.footprint(k.grid_pose, *cloud) : std::vector<map::BlockKey>{};
    k.footprint_pose = k.grid_pose;
  }
  return k.footprint;
}

int updateGrid(map::SemanticOccupancyMap& grid, std::vector<Keyframe>& keyframes,
               std::size_t in_grid, const std::vector<Eigen::Isometry3d>& estimates,
               const RegionRule& rule) {
  const auto estimate = [&](const Keyframe& k) -> const Eigen::Isometry3d& {
    return estimates[static_cast<std::size_t>(k.id)];
  };
  const std::vector<std::size_t> moved =
      rule.enabled ? movedKeyframes(keyframes, in_grid, estimates, rule.min_shift, rule.lever)
                   : std::vector<std::size_t>{};
  const auto most = [&](std::size_t reaching) {
    return static_cast<double>(reaching) > rule.max_share * static_cast<double>(in_grid);
  };
  map::BlockRegion region;  // where the moved keyframes were, then also where they go
  for (const std::size_t i : moved) region.add(gridFootprint(grid, keyframes[i]));
  std::vector<bool> reaches(in_grid, false);
  // Where they were may already reach most keyframes: then where they go is not traced.
  bool whole = !rule.enabled || most(markReaching(grid, keyframes, in_grid, region, reaches));
  if (!whole) {
    map::BlockRegion going;  // tested only against the keyframes not reaching yet
    for (const std::size_t i : moved) {
      keyframes[i].grid_pose = estimate(keyframes[i]);
      const std::vector<map::BlockKey>& footprint = gridFootprint(grid, keyframes[i]);
      going.add(footprint);  // integrated there below
      region.add(footprint);
    }
    whole = most(markReaching(grid, keyframes, in_grid, going, reaches));
  }
  std::size_t kept = in_grid;  // keyframes whose scans stay in the grid
  if (whole) {
    grid.clear();
    kept = 0;
  } else if (!region.empty()) {
    grid.erase(region);
  }
  int integrated = 0;
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    Keyframe& k = keyframes[i];
    if (i >= kept || k.scan.empty()) k.grid_pose = estimate(k);
    if (i >= kept && !rule.enabled)
      integrated += integrateUnlisted(grid, k) ? 1 : 0;
    else if (i >= kept)
      integrated += integrateWhole(grid, k) ? 1 : 0;
    else if (reaches[i])
      integrated += integrateScan(grid, k.grid_pose, k.scan, &region) ? 1 : 0;
  }
  return integrated;
}

std::size_t footprintBytes(const std::vector<Keyframe>& keyframes) {
  std::size_t bytes = 0;
  for (const Keyframe& k : keyframes) bytes += k.footprint.capacity() * sizeof(map::BlockKey);
  return bytes;
}

}  // namespace socc::consistency
