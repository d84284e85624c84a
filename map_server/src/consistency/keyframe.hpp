#pragma once
// A keyframe: what the consistency service keeps of one integrated scan to find the place again
// and to register against it later. Compact: the scan downsampled to a coarse voxel grid, its
// pose as integrated (the robot's odometry in the map frame) and its place descriptor.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gravity_reference.hpp"
#include "keyframe_scan.hpp"
#include "scan_context.hpp"

namespace socc::consistency {

struct Keyframe {
  int id = 0;        // index in the service's keyframe list (= pose graph node)
  int robot = 0;     // index of the robot (order of first appearance)
  int robot_kf = 0;  // index among the robot's own keyframes
  std::int64_t seq = 0;
  std::int64_t utime = 0;
  Eigen::Isometry3d odom_pose = Eigen::Isometry3d::Identity();  // map_T_sensor as integrated
  double travelled = 0.0;  // [m] the robot's path length up to this keyframe
  // The up direction its INTEGRATE carried (sensor frame; none: the robot has no reference).
  std::optional<GravityReference> gravity = std::nullopt;
  std::vector<Eigen::Vector3f> points;  // sensor frame, voxel-downsampled
  ScanContext descriptor;
  KeyframeScan scan;  // what the grid is rebuilt from (finer, with labels)
  // Where the keyframe's scan is in the grid now: as integrated, then its pose in the last
  // rebuild. A closure that moves some keyframe far from it rebuilds the grid.
  Eigen::Isometry3d grid_pose = Eigen::Isometry3d::Identity();
  // The blocks its scan changes at footprint_pose (none: not known yet), kept for region
  // rebuilds (grid_rebuild.hpp, updateGrid): they test every keyframe, and a keyframe's
  // grid_pose mostly stays. Listed as it is integrated; not stored, traced again when needed.
  std::optional<Eigen::Isometry3d> footprint_pose;
  std::vector<Eigen::Vector3i> footprint;
  std::uint64_t order = 0;  // observation order over all robots (the rebuild's tail)

  std::size_t bytes() const {
    return sizeof(Keyframe) + points.capacity() * sizeof(Eigen::Vector3f) + descriptor.bytes() +
           scan.bytes();
  }
};

}  // namespace socc::consistency
