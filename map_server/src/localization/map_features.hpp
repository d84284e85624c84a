#pragma once
// The map's descriptors for LOCALIZE, described in two steps on two threads
// (docs/relocalization.md, "Threading"): the keypoints and their normals, turned towards the
// side the map's rays cleared, need the grid and are made on the map's thread; their FPFH and
// search trees, the costly part, need no grid and are built by the first search that uses
// them, on the search thread. Shared by every search until the map changed enough.
#include <memory>
#include <mutex>

#include "feature_cloud.hpp"
#include "hypothesis_search.hpp"

namespace socc::localization {

class MapFeatures {
 public:
  MapFeatures(OrientedKeypoints keypoints, const FeatureParams& params)
      : keypoints_(std::move(keypoints)), params_(params) {}

  /// The descriptors with their trees: built at the first call (any thread, once), the same
  /// object after.
  const IndexedFeatures& get();

 private:
  OrientedKeypoints keypoints_;  // released once described
  FeatureParams params_;
  std::once_flag once_;
  std::unique_ptr<const IndexedFeatures> built_;
};

}  // namespace socc::localization
