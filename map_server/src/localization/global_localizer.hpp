#pragma once
// Global localization of a scan in the map without a pose prior (service LOCALIZE,
// docs/relocalization.md). FPFH keypoints of scan and map (feature_cloud.hpp) are matched by
// RANSAC over feature correspondences (hypothesis_search.hpp), each hypothesis scored by the
// scan keypoints it explains minus the share of the scan it puts into the map's free space.
// The best distinct hypotheses are returned. They are hypotheses, not answers: the client
// verifies each with SOCC-ICP and its health check before it trusts one.
//
// The map's descriptors are cached. They are rebuilt when the map's occupied voxels changed by
// more than rebuild_change since the last build (new ground mapped), not at every Integrate: a
// live map changes with every scan, a rebuild of a large map takes seconds.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "feature_cloud.hpp"
#include "hypothesis_search.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::localization {

struct LocalizerParams {
  FeatureParams features;
  SearchParams search;
  // Scan points (of those sent) on which the search checks a hypothesis' free-space conflict.
  int conflict_points = 512;
  double rebuild_change = 0.02;  // relative change of occupied voxels that rebuilds
};

struct LocalizeHint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;            // [rad]
  double radius = 0.0;         // [m]
  double yaw_tolerance = 4.0;  // [rad]; >= pi: any heading
};

struct PoseCandidate {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // map_T_sensor
  int inliers = 0;
  double inlier_fraction = 0.0;
  double conflict = 0.0;  // share of the checked scan points in the map's free space
  double score = 0.0;     // inlier_fraction - conflict: the rank
};

struct LocalizeAnswer {
  std::vector<PoseCandidate> candidates;  // best first
  std::size_t map_keypoints = 0;
  std::size_t scan_keypoints = 0;
  SearchStats search;  // the budget the search spent
};

class GlobalLocalizer {
 public:
  explicit GlobalLocalizer(LocalizerParams params = {});
  ~GlobalLocalizer();
  GlobalLocalizer(GlobalLocalizer&&) noexcept;
  GlobalLocalizer& operator=(GlobalLocalizer&&) noexcept;

  /// Up to max_candidates distinct poses of scan (sensor frame) in map, best first.
  LocalizeAnswer localize(const map::SemanticOccupancyMap& map,
                          const std::vector<Eigen::Vector3f>& scan,
                          const std::optional<LocalizeHint>& hint, int max_candidates);

  /// Map keypoints of the current descriptor cache (0 before the first localize()).
  std::size_t mapKeypoints() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Heading of a pose: the sensor's x axis about the map's z axis [rad].
double yawOf(const Eigen::Isometry3d& pose);

/// Where a scan's points (sensor frame) land in the map at pose.
struct SpaceCheck {
  double observed = 0.0;  // share of the points in voxels the map observed
  double free = 0.0;      // of those, the share in free space, weighed by its evidence (0..1)
};
SpaceCheck checkFreeSpace(const map::SemanticOccupancyMap& map,
                          const std::vector<Eigen::Vector3f>& scan, const Eigen::Isometry3d& pose);

}  // namespace socc::localization
