#pragma once
// A grid rebuilt from the keyframe scans at their optimized poses (docs/consistency.md, "Map
// correction"), built off the LCM thread and swapped in by the map service.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "keyframe_scan.hpp"
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

/// Integrates scan at pose with the map's own integrator; false (nothing changed) when the
/// map refuses it (map::SemanticOccupancyMap::validate).
bool integrateScan(map::SemanticOccupancyMap& map, const Eigen::Isometry3d& pose,
                   const KeyframeScan& scan);

/// How far moving a keyframe from `from` to `to` moves its scan: the translation plus the
/// rotation's sweep at lever metres.
double poseShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double lever);

}  // namespace socc::consistency
