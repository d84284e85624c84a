#pragma once
// The map keypoints' positions for the search's inlier tests: the nearest keypoint of a point
// (nanoflann's k-d tree). These lookups are most of a search's work (0.4-1.4 M per request on
// the street benchmark); on nanoflann instead of PCL's KdTreeFLANN the same lookups took a
// search from 2.00 to 1.14 s (docs/relocalization.md "200 candidates per keypoint"), and bounded
// by the inlier distance (no branch beyond it entered) 0.56 s, with the same answers.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <optional>

namespace socc::localization {

class KeypointIndex {
 public:
  KeypointIndex();
  /// Indexes keypoints (kept alive by the index).
  explicit KeypointIndex(pcl::PointCloud<pcl::PointNormal>::ConstPtr keypoints);
  ~KeypointIndex();
  KeypointIndex(KeypointIndex&&) noexcept;
  KeypointIndex& operator=(KeypointIndex&&) noexcept;

  struct Nearest {
    int index = -1;
    float squared_distance = 0.f;
  };
  /// The keypoint nearest to p when it lies within squared distance radius2 of it.
  std::optional<Nearest> nearestWithin(const Eigen::Vector3f& p, float radius2) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;  // on the heap: nanoflann holds a reference to its adaptor
};

}  // namespace socc::localization
