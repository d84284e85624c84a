#pragma once
// Test helper: how much of one cloud lies within a distance of another (nearest neighbour by
// nanoflann's k-d tree), for comparing decoded clouds with vendors' reference clouds.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <nanoflann.hpp>
#include <utility>
#include <vector>

namespace socc::sensors::test_io {

class NearestPoints {
 public:
  explicit NearestPoints(const std::vector<Eigen::Vector3f>& cloud)
      : adaptor_{cloud}, tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree_.buildIndex();
  }
  /// Squared distance from q to the nearest point (infinity for an empty cloud).
  float squaredDistance(const Eigen::Vector3f& q) const {
    if (adaptor_.cloud.empty()) return std::numeric_limits<float>::infinity();
    unsigned index = 0;  // nanoflann 1.4's index type
    float d2 = 0.f;
    tree_.knnSearch(q.data(), 1, &index, &d2);
    return d2;
  }
  /// Squared distance and index of the nearest point (the cloud must not be empty).
  std::pair<float, std::size_t> nearest(const Eigen::Vector3f& q) const {
    unsigned index = 0;
    float d2 = 0.f;
    tree_.knnSearch(q.data(), 1, &index, &d2);
    return {d2, index};
  }
  /// Indices of the k nearest points.
  std::vector<unsigned> knn(const Eigen::Vector3f& q, std::size_t k) const {
    std::vector<unsigned> index(k);
    std::vector<float> d2(k);
    index.resize(tree_.knnSearch(q.data(), k, index.data(), d2.data()));
    return index;
  }
  /// Fraction of query's points within radius of the cloud.
  double fractionWithin(const std::vector<Eigen::Vector3f>& query, float radius) const {
    std::size_t near = 0;
    for (const auto& q : query) near += squaredDistance(q) <= radius * radius ? 1 : 0;
    return query.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(query.size());
  }

 private:
  struct Adaptor {
    const std::vector<Eigen::Vector3f>& cloud;
    std::size_t kdtree_get_point_count() const { return cloud.size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const {
      return cloud[i][static_cast<int>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>, Adaptor, 3>;
  Adaptor adaptor_;
  Tree tree_;
};

}  // namespace socc::sensors::test_io
