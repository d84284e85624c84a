#include "keypoint_index.hpp"

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
  unsigned nearest = 0;
  float d2 = 0.f;
  if (tree_->index.knnSearch(p.data(), 1, &nearest, &d2) != 1 || d2 > radius2) return std::nullopt;
  return Nearest{static_cast<int>(nearest), d2};
}

}  // namespace socc::localization
