#include "keypoint_index.hpp"

#include <cmath>
#include <limits>
#include <nanoflann.hpp>

namespace socc::localization {

struct KeypointIndex::Tree {
  struct Adaptor {
    pcl::PointCloud<pcl::PointNormal>::ConstPtr cloud;
    std::size_t kdtree_get_point_count() const { return cloud->size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const {
      return (*cloud)[i].data[dim];  // x, y, z
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>,
                                                    Adaptor, 3, unsigned>;

  explicit Tree(pcl::PointCloud<pcl::PointNormal>::ConstPtr keypoints)
      : adaptor{std::move(keypoints)},
        index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    index.buildIndex();
  }
  Adaptor adaptor;
  Index index;
};

namespace {

// The nearest point within a squared distance bound: the tree's branches farther than the bound
// are never entered, where a plain nearest-neighbour search goes on to the nearest keypoint
// however far (most points of a wrong hypothesis land far from every keypoint). It returns what
// that search returns when its nearest is within the bound: the first point visited at the
// smallest distance (nanoflann hands a leaf's points over while they are below worstDist()).
class NearestWithinBound {
 public:
  explicit NearestWithinBound(float bound2)
      : worst_(std::nextafter(bound2, std::numeric_limits<float>::infinity())) {}
  bool full() const { return true; }
  bool addPoint(float d2, unsigned index) {
    if (d2 < worst_) {
      worst_ = d2;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  float worstDist() const { return worst_; }
  std::optional<KeypointIndex::Nearest> result() const {
    if (!found_) return std::nullopt;
    return KeypointIndex::Nearest{static_cast<int>(index_), worst_};
  }

 private:
  float worst_;
  unsigned index_ = 0;
  bool found_ = false;
};

}  // namespace

KeypointIndex::KeypointIndex() = default;
KeypointIndex::KeypointIndex(pcl::PointCloud<pcl::PointNormal>::ConstPtr keypoints) {
  if (keypoints && !keypoints->empty()) tree_ = std::make_unique<Tree>(std::move(keypoints));
}
KeypointIndex::~KeypointIndex() = default;
KeypointIndex::KeypointIndex(KeypointIndex&&) noexcept = default;
KeypointIndex& KeypointIndex::operator=(KeypointIndex&&) noexcept = default;

std::optional<KeypointIndex::Nearest> KeypointIndex::nearestWithin(const Eigen::Vector3f& p,
                                                                   float radius2) const {
  if (!tree_) return std::nullopt;
  NearestWithinBound result(radius2);
  tree_->index.findNeighbors(result, p.data(), nanoflann::SearchParams());
  return result.result();
}

}  // namespace socc::localization
