#pragma once
// A grid rebuilt from the keyframe scans at their optimized poses (docs/consistency.md, "Map
// correction"), built off the LCM thread and swapped in by the map service.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "consistency_params.hpp"
#include "keyframe.hpp"
#include "keyframe_scan.hpp"
#include "socc/map/block_region.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::consistency {

struct RebuiltGrid {
  explicit RebuiltGrid(const map::MapConfig& config) : map(config) {}

  map::SemanticOccupancyMap map;
  /// Per robot: its integrations' poses as first integrated (the odometry's frame) to the
  /// corrected map frame, from its newest keyframe in the rebuild.
  std::map<std::string, Eigen::Isometry3d> corrections;
  /// Keyframes observed before order `mark` are in map; later ones are its tail.
  std::uint64_t mark = 0;
  struct Tail {
    std::string robot;
    Eigen::Isometry3d raw_pose = Eigen::Isometry3d::Identity();
    KeyframeScan scan;
  };
  /// Tail keyframes the worker processed after the rebuild was ready: integrated at the swap.
  std::vector<Tail> tail;
  int serial = 0;          // the service's rebuilds counted from 1 (its store's record)
  int keyframes = 0;       // scans integrated by the worker
  double seconds = 0.0;    // the worker's time for them
  double max_shift = 0.0;  // [m] the largest keyframe move that asked for it
};

/// The keyframes' part of the last rebuilt grid, kept by the worker: the next rebuild starts
/// from a copy of it and integrates again only the region whose keyframes moved.
struct KeyframeGrid {
  map::SemanticOccupancyMap map;
  std::size_t keyframes = 0;  // keyframes [0, keyframes) are in map, each at its grid_pose
};

/// Integrates scan at pose with the map's own integrator (changing only within's blocks when
/// given); false (nothing changed) when the map refuses it (map::SemanticOccupancyMap::validate).
bool integrateScan(map::SemanticOccupancyMap& map, const Eigen::Isometry3d& pose,
                   const KeyframeScan& scan, const map::BlockRegion* within = nullptr);

/// The keyframe's footprint at its grid_pose (SemanticOccupancyMap::footprint; empty when
/// map refuses its scan), traced again only when not known there.
const std::vector<map::BlockKey>& gridFootprint(map::SemanticOccupancyMap& map, Keyframe& keyframe);

/// When a rebuild works on a region (ConsistencyParams' rebuild_region, rebuild_region_shift,
/// rebuild_lever, rebuild_region_max_share).
struct RegionRule {
  bool enabled;      // false: every rebuild is whole, and no footprint is listed or kept
  double min_shift;  // [m] keyframes moving less (poseShift at lever) stay where they are
  double lever;      // [m]
  double max_share;  // a region reaching more of the keyframes: rebuilt whole
};

inline RegionRule regionRule(const ConsistencyParams& p) {
  return {p.rebuild_region, p.rebuild_region_shift, p.rebuild_lever, p.rebuild_region_max_share};
}

/// Brings grid, which holds keyframes [0, in_grid) at their grid_pose, to every keyframe at
/// its estimate (estimates[id]): keyframes that moved more than rule.min_shift make the region
/// (their scans' footprints where they were and where they go), which is erased and integrated
/// again from every keyframe whose footprint reaches into it, in keyframe order; keyframes from
/// in_grid on are integrated whole (listing their footprints). What lies outside the region
/// stays: the keyframes that did not move keep their grid_pose there and in it, so each
/// keyframe is in the grid at one pose. With in_grid 0 (an empty grid), or a region reaching
/// more than rule.max_share of the keyframes, it is the whole rebuild, every keyframe at its
/// estimate; so is every rebuild when !rule.enabled (then without footprints). Returns the scans
/// integrated.
int updateGrid(map::SemanticOccupancyMap& grid, std::vector<Keyframe>& keyframes,
               std::size_t in_grid, const std::vector<Eigen::Isometry3d>& estimates,
               const RegionRule& rule);

/// The memory of the keyframes' footprints (what region rebuilds keep besides the grid).
std::size_t footprintBytes(const std::vector<Keyframe>& keyframes);

/// How far moving a keyframe from `from` to `to` moves its scan: the translation plus the
/// rotation's sweep at lever metres.
double poseShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double lever);

}  // namespace socc::consistency
