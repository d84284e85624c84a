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
// live map changes with every scan, a rebuild of a large map takes seconds. A rebuild's grid
// part (keypoints, normals turned to the free side) runs in prepare(); its FPFH and trees in the
// first search's run() (map_features.hpp).
//
// A search runs in three parts (localize_search.hpp): prepare and finish need the map (its
// thread), LocalizeSearch::run does not; localize() runs all three in turn.
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "localize_search.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::localization {

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

  /// The search of localize() before it runs: map's descriptors (rebuilt when map changed
  /// enough) and the scan. On the map's thread.
  LocalizeSearch prepare(const map::SemanticOccupancyMap& map, std::vector<Eigen::Vector3f> scan,
                         const std::optional<LocalizeHint>& hint, int max_candidates);
  /// localize()'s answer from a search that ran: its hypotheses ranked by their free-space
  /// conflict in map as it is now, those within the hint, at most max_candidates. On the map's
  /// thread.
  static LocalizeAnswer finish(const map::SemanticOccupancyMap& map, LocalizeSearch search);

  /// Map keypoints of the current descriptor cache (0 before the first localize()); describes
  /// the cache when no search did yet.
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
