#pragma once
// The RANSAC stage of global localization (docs/relocalization.md): pose hypotheses of a scan in
// the map from FPFH correspondences, built from PCL's parts (feature KD-tree, SVD pose
// estimation) and a nanoflann index of the map keypoints (keypoint_index.hpp).
//
// Why not SampleConsensusPrerejective: it draws three correspondences independently, each among
// the few nearest features of its scan keypoint, and needs all three right. On a street of
// repeated structure FPFH ranks the right map keypoint among the 6 nearest features for about
// 1 % of the scan keypoints (among the 30 nearest for about 4 %), so almost no draw is right.
// And a run returns one pose, the one whose inliers lie closest on average among all poses with
// a minimum inlier share, which in a repetitive world is a lookalike's more often than not.
//
// Here a sample grows from one correspondence: the next scan keypoints take, among their
// correspondence_randomness nearest features, one whose distances to the map keypoints already
// chosen equal the scan's (rigid motions keep distances). One right first pair is then enough,
// and the candidate lists can be long. A hypothesis' inliers (scan keypoints within
// inlier_distance of a map keypoint) are counted in blocks and most are given up after the first
// block; the `keep` distinct hypotheses with the most inliers are kept and refined on their
// inliers (searchHypotheses: no grid needed, any thread), then ranked by
//   score = inlier share - conflict (the share of the scan the pose puts into the map's free
//           space, ConflictAt; rankHypotheses: needs the live grid, the map's thread).
#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "feature_cloud.hpp"
#include "keypoint_index.hpp"

namespace socc::localization {

struct SearchParams {
  // Samples drawn (a draw that finds no partners counts too). A count, not a time: the answer
  // is the same on a quiet and a loaded machine; each draw's cost is bounded (docs).
  int max_iterations = 30'000;
  // Scan keypoints tested as inliers, over all draws, at most: bounds the search's work (and so
  // its latency) whatever the scan, again as a count.
  std::int64_t max_inlier_tests = 4'000'000;
  // Candidates of a scan keypoint: its nearest map features. The right map keypoint is among
  // the 30 nearest for ~4 % of socc-sim street scan keypoints, among the 200 nearest for
  // 12-20 %; a sample's partners are picked by distance consistency among these, so the longer
  // list finds a right first pair's right partners more often (docs/relocalization.md).
  int correspondence_randomness = 200;
  double edge_tolerance = 1.0;        // [m] a sample's edge lengths in scan and map agree this well
  double min_edge = 2.0;              // [m] sample points closer than this fix no rotation
  double inlier_distance = 1.0;       // [m] keypoint match distance (one keypoint spacing)
  double min_inlier_fraction = 0.1;   // of the scan keypoints, for a hypothesis to count
  int keep = 32;                      // distinct hypotheses kept
  double distinct_translation = 2.0;  // [m] hypotheses closer than this and
  double distinct_rotation = 0.17;    // [rad] this are one (about 10 deg)
  unsigned seed = 1;                  // of the sampling: answers are reproducible
};

/// Keypoints and features of the map with their search trees (built once per map version).
struct IndexedFeatures {
  explicit IndexedFeatures(FeatureCloud cloud);
  FeatureCloud cloud;
  KeypointIndex positions;
  pcl::KdTreeFLANN<pcl::FPFHSignature33> features;
};

/// Share of the scan a pose puts into the map's free space (0: none, 1: all), for the ranking.
using ConflictAt = std::function<double(const Eigen::Isometry3d& map_T_scan)>;

struct Hypothesis {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // map_T_scan
  int inliers = 0;
  double inlier_fraction = 0.0;
  double conflict = 0.0;
  double score = 0.0;  // inlier_fraction - conflict: the rank
};

/// The work a search did (the budget spent).
struct SearchStats {
  int draws = 0;               // samples drawn
  long long inlier_tests = 0;  // scan keypoints tested against the map's keypoints
  bool cancelled = false;      // stopped by its cancel flag: found nothing
};

/// The kept hypotheses (at most params.keep), refined, not yet ranked (score = inlier share).
/// Touches no grid. cancel (may be null) is polled between draws: once set, the search stops
/// and returns nothing; otherwise the answer depends on the inputs and params.seed alone.
std::vector<Hypothesis> searchHypotheses(const IndexedFeatures& map, const FeatureCloud& scan,
                                         const SearchParams& params, SearchStats* stats = nullptr,
                                         const std::atomic<bool>* cancel = nullptr);

/// Scores found by its free-space conflict and keeps one per place, best score first.
std::vector<Hypothesis> rankHypotheses(std::vector<Hypothesis> found, const ConflictAt& conflict,
                                       const SearchParams& params);

}  // namespace socc::localization
