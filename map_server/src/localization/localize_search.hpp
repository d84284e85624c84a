#pragma once
// One LOCALIZE search, split by what each part touches (docs/relocalization.md, "Threading"):
// GlobalLocalizer::prepare snapshots what the search needs from the map on the map's thread
// (the map's descriptors, shared and immutable); run() describes the scan and draws the
// hypotheses on any thread, touching no grid; GlobalLocalizer::finish ranks them by the live
// grid's free space, again on the map's thread.
#include <Eigen/Geometry>
#include <atomic>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "feature_cloud.hpp"
#include "hypothesis_search.hpp"
#include "map_features.hpp"

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
  std::size_t scan_keypoints = 0;  // 0 when not described: the map has fewer than 3 keypoints
  SearchStats search;              // the budget the search spent
};

class LocalizeSearch {
 public:
  /// The map's descriptors when no search described them yet (MapFeatures), the scan's, and
  /// the hypothesis search. Touches no grid: safe on any thread
  /// while the map changes. cancel (may be null) is polled between draws; a cancelled search
  /// finds nothing (answer().search.cancelled).
  void run(const std::atomic<bool>* cancel = nullptr);

  const LocalizeAnswer& answer() const { return answer_; }

 private:
  friend class GlobalLocalizer;

  LocalizerParams params_;
  std::shared_ptr<MapFeatures> map_;   // the descriptors at prepare time (described by run())
  std::vector<Eigen::Vector3f> scan_;  // sensor frame
  std::optional<LocalizeHint> hint_;
  int max_candidates_ = 0;
  LocalizeAnswer answer_;          // keypoint counts and the budget spent, by run()
  std::vector<Hypothesis> found_;  // by run(), unranked
};

}  // namespace socc::localization
