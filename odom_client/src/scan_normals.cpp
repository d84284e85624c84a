#include "socc/odom/scan_normals.hpp"

#include <algorithm>
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
// Points of one scan line (a ring) share the beam's elevation seen from the sensor: fitted alone
// they give the plane of the beam's cone, not the surface (a ring across a pole, a car or a
// trunk is a flat curve). Paired along that normal, the ring is pulled to where an earlier
// sweep's ring lay, i.e. the sensor to the tilt it had then. A neighbourhood must span more
// elevation than this: half the finest ring spacing of spinning LiDARs (0.11 deg, VLS-128).
// Not on the ground: a ring across it is a curve in its plane.
constexpr double kMinElevationSpread = 0.05 * M_PI / 180.0;

// Elevation [rad] of a point seen from the sensor (the cloud's origin).
double elevation(const Eigen::Vector3f& p) {
  return std::atan2(double{p.z()}, std::hypot(double{p.x()}, double{p.y()}));
}

}  // namespace

struct ScanNormals::Search {
  Search(Points cloud, double r, double threshold, std::vector<std::uint8_t> ground)
      : points(std::move(cloud)),
        on_ground(std::move(ground)),
        radius(r),
        planarity_threshold(threshold),
        adaptor{&points},
        tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    tree.buildIndex();
  }
  Eigen::Vector3f normalAt(std::size_t i) const;

  const Points points;
  const std::vector<std::uint8_t> on_ground;
  const double radius;
  const double planarity_threshold;
  const CloudAdaptor adaptor;  // the tree keeps a reference to it
  Tree tree;
};

Eigen::Vector3f ScanNormals::Search::normalAt(std::size_t i) const {
  std::array<std::size_t, kNeighbours> index{};
  std::array<float, kNeighbours> squared{};
  nanoflann::KNNResultSet<float, std::size_t> result(kNeighbours);
  result.init(index.data(), squared.data());
  // The result set's worst distance starts at the radius instead of infinity: the search prunes
  // what lies beyond it (the same neighbours; an isolated point no longer searches far).
  squared.back() = std::nextafter(static_cast<float>(radius * radius), HUGE_VALF);
  tree.findNeighbors(result, points[i].data(), nanoflann::SearchParams());
  PointMoments moments;
  double lowest = HUGE_VAL, highest = -HUGE_VAL;
  for (std::size_t k = 0; k < result.size(); ++k) {
    if (squared[k] > radius * radius) continue;
    const Eigen::Vector3f& p = points[index[k]];
    moments.add(p.cast<double>());
    const double e = elevation(p);
    lowest = std::min(lowest, e);
    highest = std::max(highest, e);
  }
  const bool ground = i < on_ground.size() && on_ground[i] != 0;
  if (highest - lowest < kMinElevationSpread && !ground)
    return Eigen::Vector3f::Zero();  // one ring
  const VoxelFeatures f = voxelFeatures(sampleCovariance(moments.m2(), moments.count),
                                        moments.count, EigenSolver::kIterative);
  const bool plane = f.valid && f.planarity < planarity_threshold &&
                     f.eigenvalues[0] < kMaxFlatRatio * f.eigenvalues[1];
  return plane ? Eigen::Vector3f(f.normal.cast<float>()) : Eigen::Vector3f::Zero();
}

ScanNormals::ScanNormals(Points points, double radius, double planarity_threshold,
                         std::vector<std::uint8_t> on_ground)
    : normals_(points.size(), Eigen::Vector3f::Zero()), known_(points.size(), 0) {
  if (points.size() < kMinPointsForFeatures)
    known_.assign(known_.size(), 1);  // no plane anywhere
  else
    search_ = std::make_unique<const Search>(std::move(points), radius, planarity_threshold,
                                             std::move(on_ground));
}

ScanNormals::~ScanNormals() = default;
ScanNormals::ScanNormals(ScanNormals&&) noexcept = default;
ScanNormals& ScanNormals::operator=(ScanNormals&&) noexcept = default;

const Eigen::Vector3f& ScanNormals::at(std::size_t i) const {
  if (!known_[i]) {
    normals_[i] = search_->normalAt(i);
    known_[i] = 1;
  }
  return normals_[i];
}

}  // namespace socc::odom
