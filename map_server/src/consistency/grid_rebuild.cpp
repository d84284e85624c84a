#include "grid_rebuild.hpp"

namespace socc::consistency {

bool integrateScan(map::SemanticOccupancyMap& map, const Eigen::Isometry3d& pose,
                   const KeyframeScan& scan, const map::BlockRegion* within) {
  if (scan.empty()) return false;
  const LabeledCloud cloud = scan.cloud();
  if (!map.validate(pose, cloud).empty()) return false;
  if (within != nullptr)
    map.integrate(pose, cloud, *within);
  else
    map.integrate(pose, cloud);
  return true;
}

double poseShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double lever) {
  const double angle = Eigen::AngleAxisd(from.linear().transpose() * to.linear()).angle();
  return (to.translation() - from.translation()).norm() + angle * lever;
}

Eigen::AlignedBox3d scanBox(const KeyframeScan& scan, const Eigen::Isometry3d& pose,
                            const map::MapConfig& config) {
  Eigen::AlignedBox3d box(pose.translation());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    Eigen::Vector3d p(scan.xyz[0][i], scan.xyz[1][i], scan.xyz[2][i]);
    p *= scan.resolution;
    const double range = p.norm();
    if (range > config.max_range) p *= config.max_range / range;
    box.extend(pose * p);
  }
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(config.voxel_size);
  return {box.min() - margin, box.max() + margin};
}

const Eigen::AlignedBox3d& gridBox(Keyframe& keyframe, const map::MapConfig& config) {
  if (keyframe.box.isEmpty() || keyframe.box_pose.matrix() != keyframe.grid_pose.matrix()) {
    keyframe.box = scanBox(keyframe.scan, keyframe.grid_pose, config);
    keyframe.box_pose = keyframe.grid_pose;
  }
  return keyframe.box;
}

int updateGrid(map::SemanticOccupancyMap& grid, std::vector<Keyframe>& keyframes,
               std::size_t in_grid, const std::vector<Eigen::Isometry3d>& estimates,
               double min_shift, double lever) {
  const map::MapConfig& config = grid.config();
  const auto estimate = [&](const Keyframe& k) -> const Eigen::Isometry3d& {
    return estimates[static_cast<std::size_t>(k.id)];
  };
  map::BlockRegion region;
  std::vector<bool> moved(in_grid, false);
  for (std::size_t i = 0; i < in_grid; ++i) {
    Keyframe& k = keyframes[i];
    if (k.scan.empty() || poseShift(k.grid_pose, estimate(k), lever) <= min_shift) continue;
    moved[i] = true;
    region.addBox(gridBox(k, config), config.voxel_size);
    k.box = scanBox(k.scan, estimate(k), config);  // gridBox's, once grid_pose moves there
    k.box_pose = estimate(k);
    region.addBox(k.box, config.voxel_size);
  }
  if (!region.empty()) grid.erase(region);
  int integrated = 0;
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    Keyframe& k = keyframes[i];
    if (i >= in_grid || moved[i] || k.scan.empty()) k.grid_pose = estimate(k);
    if (i >= in_grid) {
      integrated += integrateScan(grid, k.grid_pose, k.scan) ? 1 : 0;
    } else if (!region.empty() && !k.scan.empty() &&
               region.intersects(gridBox(k, config), config.voxel_size)) {
      integrated += integrateScan(grid, k.grid_pose, k.scan, &region) ? 1 : 0;
    }
  }
  return integrated;
}

}  // namespace socc::consistency
