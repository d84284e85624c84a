#include "socc/odom/scan_normals.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <nanoflann.hpp>

#include "socc/voxel.hpp"

namespace socc::odom {
namespace {

struct CloudAdaptor {
  const Points* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>,
                                                 CloudAdaptor, 3, std::size_t>;

constexpr std::size_t kNeighbours = 12;
// The normal must be defined by two directions of extent, not by noise across one ring's line:
// the smallest eigenvalue well below the middle one.
constexpr double kMaxFlatRatio = 0.1;

Eigen::Vector3f normalAt(const Tree& tree, const Points& points, std::size_t i, double radius,
                         double planarity_threshold) {
  std::array<std::size_t, kNeighbours> index{};
  std::array<float, kNeighbours> squared{};
  nanoflann::KNNResultSet<float, std::size_t> result(kNeighbours);
  result.init(index.data(), squared.data());
  // The result set's worst distance starts at the radius instead of infinity: the search prunes
  // what lies beyond it (the same neighbours; an isolated point no longer searches far).
  squared.back() = std::nextafter(static_cast<float>(radius * radius), HUGE_VALF);
  tree.findNeighbors(result, points[i].data(), nanoflann::SearchParams());
  PointMoments moments;
  for (std::size_t k = 0; k < result.size(); ++k)
    if (squared[k] <= radius * radius) moments.add(points[index[k]].cast<double>());
  const VoxelFeatures f = voxelFeatures(sampleCovariance(moments.m2(), moments.count),
                                        moments.count, EigenSolver::kIterative);
  const bool plane = f.valid && f.planarity < planarity_threshold &&
                     f.eigenvalues[0] < kMaxFlatRatio * f.eigenvalues[1];
  return plane ? Eigen::Vector3f(f.normal.cast<float>()) : Eigen::Vector3f::Zero();
}

}  // namespace

Points scanNormals(const Points& points, double radius, double planarity_threshold) {
  Points normals(points.size(), Eigen::Vector3f::Zero());
  if (points.size() < kMinPointsForFeatures) return normals;
  const CloudAdaptor adaptor{&points};
  Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      normals[i] = normalAt(tree, points, i, radius, planarity_threshold);
  });
  return normals;
}

}  // namespace socc::odom
