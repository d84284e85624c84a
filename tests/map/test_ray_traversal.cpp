// Amanatides-Woo traversal against brute force.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "socc/map/ray_footprint.hpp"
#include "socc/map/ray_traversal.hpp"

namespace socc::map {
namespace {

using Key = std::array<int, 3>;
Key key(const VoxelIndex& v) {
  return {v.x(), v.y(), v.z()};
}

/// Does segment [a, b] intersect the voxel's closed box, grown by eps? (slab test)
bool intersects(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const VoxelIndex& v, double vs,
                double eps) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double lo = v[i] * vs - eps, hi = (v[i] + 1) * vs + eps;
    const double d = b[i] - a[i];
    if (std::abs(d) < 1e-15) {
      if (a[i] < lo || a[i] > hi) return false;
      continue;
    }
    double ta = (lo - a[i]) / d, tb = (hi - a[i]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

TEST(RayTraversal, MatchesBruteForceOnRandomRays) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  const double vs = 0.5;
  for (int ray = 0; ray < 500; ++ray) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng));
    Eigen::Vector3d b(u(rng), u(rng), u(rng));
    if (ray % 10 == 0) b.y() = a.y();  // axis-parallel components
    if (ray % 20 == 0) b.z() = a.z();
    std::vector<VoxelIndex> voxels;
    traverseRay(a, b, vs, voxels);
    ASSERT_FALSE(voxels.empty());
    EXPECT_EQ(voxels.front(), voxelIndex(a, 1.0 / vs));
    EXPECT_EQ(voxels.back(), voxelIndex(b, 1.0 / vs));
    std::set<Key> visited;
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      EXPECT_TRUE(visited.insert(key(voxels[i])).second) << "voxel visited twice";
      EXPECT_TRUE(intersects(a, b, voxels[i], vs, 1e-9)) << "voxel not on the segment";
      if (i > 0) {
        EXPECT_EQ((voxels[i] - voxels[i - 1]).cwiseAbs().sum(), 1) << "not 6-connected";
      }
    }
    // Dense samples along the segment all fall in visited voxels.
    const int samples = 20000;
    for (int s = 0; s <= samples; ++s) {
      const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(s) / samples);
      ASSERT_TRUE(visited.count(key(voxelIndex(p, 1.0 / vs))))
          << "sample voxel missing from traversal (ray " << ray << ")";
    }
  }
}

TEST(RayTraversal, SinglePointAndNegativeCoordinates) {
  std::vector<VoxelIndex> v;
  traverseRay(Eigen::Vector3d(-0.1, -0.1, -0.1), Eigen::Vector3d(-0.2, -0.2, -0.2), 0.5, v);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0], VoxelIndex(-1, -1, -1));
  v.clear();
  traverseRay(Eigen::Vector3d(0.25, 0.25, 0.25), Eigen::Vector3d(-2.25, 0.25, 0.25), 0.5, v);
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v.back(), VoxelIndex(-5, 0, 0));
}

// The voxels a footprint marks.
std::set<Key> voxelsOfFootprint(const RayFootprint& f) {
  std::set<Key> out;
  for (std::size_t b = 0; b < f.numBlocks(); ++b)
    for (int local = 0; local < kBlockVoxels; ++local)
      if ((f.mask(b)[static_cast<std::size_t>(local / 64)] >> (local % 64)) & 1u)
        out.insert(key(voxelOf(f.key(b), local)));
  return out;
}

// The footprint is the set of voxels of all rays, whichever storage it picks: a dense box
// (small extents) and the hash map (forced by a huge box) give the same blocks and masks, and
// merging two halves gives the same as marking everything into one.
TEST(RayFootprint, DenseAndHashedAgreeWithTraversal) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  const double vs = 0.5;
  const Eigen::Vector3d origin(0.3, -0.2, 1.7);
  std::vector<Eigen::Vector3d> ends(500);
  for (auto& e : ends) e = Eigen::Vector3d(u(rng), u(rng), u(rng) * 0.2);

  std::set<Key> expected;
  for (const auto& e : ends)
    forEachVoxelOnRay(origin, e, vs, [&](const VoxelIndex& v) { expected.insert(key(v)); });

  const VoxelIndex lo(-70, -70, -20), hi(70, 70, 20);
  const VoxelIndex huge(1 << 20, 1 << 20, 1 << 20);
  const auto mark = [&](RayFootprint& f, std::size_t begin, std::size_t end) {
    RayFootprint::Marker marker(f);
    for (std::size_t i = begin; i < end; ++i) forEachVoxelOnRay(origin, ends[i], vs, marker);
    f.finish();
  };
  RayFootprint dense, hashed, first_half, second_half;
  dense.reset(lo, hi);
  mark(dense, 0, ends.size());
  hashed.reset(-huge, huge);
  mark(hashed, 0, ends.size());
  first_half.reset(lo, hi);
  mark(first_half, 0, ends.size() / 2);
  second_half.reset(-huge, huge);
  mark(second_half, ends.size() / 2, ends.size());
  first_half.merge(second_half);

  EXPECT_EQ(voxelsOfFootprint(dense), expected);
  EXPECT_EQ(voxelsOfFootprint(hashed), expected);
  EXPECT_EQ(voxelsOfFootprint(first_half), expected);
  EXPECT_EQ(dense.numBlocks(), hashed.numBlocks());
  EXPECT_EQ(first_half.numBlocks(), dense.numBlocks());  // merge does not duplicate blocks
}

// markRays (rays walked several at a time in SIMD lanes, then scalar to their ends) marks the
// voxels of forEachVoxelOnRay, for ends at voxel centres (hit voxels), anywhere (max-range
// ends), on voxel faces, edges and corners (ties), along axes, in the origin's voxel, at
// negative coordinates; in any split into groups merged with absorb(), and in hash mode. The
// blocks come in key order.
TEST(RayFootprint, MarkRaysMatchesTheWalksOfEachRay) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-40.0, 40.0);
  std::uniform_int_distribution<int> cell(-80, 80);
  const double vs = 0.5;
  for (const Eigen::Vector3d& origin :
       {Eigen::Vector3d(0.3, -0.2, 1.7), Eigen::Vector3d(0.0, 0.0, 0.0),
        Eigen::Vector3d(-12.25, 7.5, -3.0)}) {
    std::vector<Eigen::Vector3d> ends;
    for (int i = 0; i < 3000; ++i) {
      const Eigen::Vector3d c(cell(rng) + 0.5, cell(rng) + 0.5, 0.2 * cell(rng) + 0.5);
      switch (i % 6) {
        case 0:  // voxel centre
        case 1:
          ends.push_back(c * vs);
          break;
        case 2:  // anywhere
          ends.emplace_back(u(rng), u(rng), 0.3 * u(rng));
          break;
        case 3:  // on faces, edges and corners of the grid
          ends.push_back(Eigen::Vector3d(std::round(c.x()), std::round(c.y()), c.z()) * vs);
          break;
        case 4:  // along an axis or a diagonal from the origin
          ends.push_back(origin + Eigen::Vector3d(c.x() * vs, i % 12 == 4 ? 0.0 : c.x() * vs,
                                                  i % 24 == 4 ? c.x() * vs : 0.0));
          break;
        default:  // within a voxel or two of the origin
          ends.push_back(origin + Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.02);
      }
    }
    std::set<Key> expected;
    VoxelIndex lo = voxelIndex(origin, 1.0 / vs), hi = lo;
    for (const auto& e : ends) {
      forEachVoxelOnRay(origin, e, vs, [&](const VoxelIndex& v) { expected.insert(key(v)); });
      lo = lo.cwiseMin(voxelIndex(e, 1.0 / vs));
      hi = hi.cwiseMax(voxelIndex(e, 1.0 / vs));
    }
    const VoxelIndex huge(1 << 20, 1 << 20, 1 << 20);
    for (const int parts : {1, 3}) {
      for (const bool dense : {true, false}) {
        std::vector<RayFootprint> footprints(static_cast<std::size_t>(parts));
        for (std::size_t p = 0; p < footprints.size(); ++p) {
          footprints[p].reset(dense ? lo : VoxelIndex(-huge), dense ? hi : huge);
          ASSERT_EQ(footprints[p].dense(), dense);
          const std::size_t begin = ends.size() * p / footprints.size();
          const std::size_t end = ends.size() * (p + 1) / footprints.size();
          footprints[p].markRays(origin, ends.data() + begin, end - begin, vs);
        }
        for (std::size_t p = 1; p < footprints.size(); ++p) footprints[0].absorb(footprints[p]);
        footprints[0].finish();
        EXPECT_EQ(voxelsOfFootprint(footprints[0]), expected) << parts << " " << dense;
        for (std::size_t b = 1; b < footprints[0].numBlocks(); ++b)
          EXPECT_TRUE(indexLess(footprints[0].key(b - 1), footprints[0].key(b)));
      }
    }
  }
}

// A footprint reused for scan after scan (different boxes) starts empty each time.
TEST(RayFootprint, ReuseStartsEmpty) {
  const double vs = 0.5;
  RayFootprint f;
  std::set<Key> last;
  for (int scan = 0; scan < 4; ++scan) {
    const Eigen::Vector3d origin(3.0 * scan, -2.0 * scan, 0.25);
    std::vector<Eigen::Vector3d> ends;
    for (int i = 0; i < 200; ++i)
      ends.push_back(origin + Eigen::Vector3d(std::cos(i * 0.1), std::sin(i * 0.1), 0.01 * i) *
                                  (5.0 + scan * 7.0));
    std::set<Key> expected;
    VoxelIndex lo = voxelIndex(origin, 1.0 / vs), hi = lo;
    for (const auto& e : ends) {
      forEachVoxelOnRay(origin, e, vs, [&](const VoxelIndex& v) { expected.insert(key(v)); });
      lo = lo.cwiseMin(voxelIndex(e, 1.0 / vs));
      hi = hi.cwiseMax(voxelIndex(e, 1.0 / vs));
    }
    f.reset(lo, hi);
    f.markRays(origin, ends.data(), ends.size(), vs);
    f.finish();
    EXPECT_EQ(voxelsOfFootprint(f), expected) << scan;
    EXPECT_NE(voxelsOfFootprint(f), last);
    last = expected;
  }
}

}  // namespace
}  // namespace socc::map
