// socc/voxel.hpp: keys floor towards -inf, moments of shifted data and added in parts, features
// of both solvers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "socc/voxel.hpp"

namespace socc {
namespace {

TEST(Voxel, IndexFloorsNegativeCoordinates) {
  EXPECT_EQ(voxelIndex({-0.01, 0.0, 0.99}, 2.0), VoxelIndex(-1, 0, 1));
  EXPECT_EQ(voxelIndex({-1.0, -0.5, 1.0}, 2.0), VoxelIndex(-2, -1, 2));
  EXPECT_TRUE(indexLess({0, 5, 5}, {1, 0, 0}));
  EXPECT_FALSE(indexLess({1, 0, 0}, {1, 0, 0}));
}

TEST(Voxel, MomentsFarFromTheOriginKeepTheirCovariance) {
  // 1e6 m away: raw sums of squares would lose the millimetre spread to cancellation.
  const Eigen::Vector3d origin(1e6, -1e6, 1e3);
  PointMoments m;
  for (int i = 0; i < 4; ++i) m.add(origin + Eigen::Vector3d(0.001 * (i % 2), 0.001 * (i / 2), 0));
  EXPECT_EQ(m.count, 4u);
  EXPECT_NEAR((m.mean() - origin).norm(), std::sqrt(2.0) * 0.0005, 1e-9);
  const Eigen::Matrix3d cov = sampleCovariance(m.m2(), m.count);
  EXPECT_NEAR(cov(0, 0), 1e-6 / 3.0, 1e-12);  // four points at 0 and 1 mm: M2 = 1e-6
  EXPECT_NEAR(cov(1, 1), 1e-6 / 3.0, 1e-12);
  EXPECT_NEAR(cov(2, 2), 0.0, 1e-12);
  EXPECT_TRUE(sampleCovariance(m.m2(), 1).isZero());
}

TEST(Voxel, MomentsAddedInPartsAreThoseOfAllThePoints) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 30; ++i)
    points.emplace_back(5.0 + 0.013 * (i % 7), -3.0 + 0.029 * (i % 5), 1.0 + 0.004 * i);
  PointMoments all, front, back, none;
  for (std::size_t i = 0; i < points.size(); ++i) {
    all.add(points[i]);
    (i < 11 ? front : back).add(points[i]);
  }
  front.add(none);  // nothing added
  none.add(front);  // an empty one takes the other's first point
  EXPECT_EQ(none.first, points[0]);
  front.add(back);
  EXPECT_EQ(front.count, all.count);
  EXPECT_EQ(front.first, all.first);
  EXPECT_NEAR((front.mean() - all.mean()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((front.m2() - all.m2()).norm(), 0.0, 1e-12);
}

TEST(Voxel, FeaturesOfAPlaneAgreeAcrossSolvers) {
  PointMoments m;
  for (int i = 0; i < 9; ++i) m.add({0.1 * (i % 3), 0.1 * (i / 3), 0.02 * (i % 2)});
  const Eigen::Matrix3d cov = sampleCovariance(m.m2(), m.count);
  const VoxelFeatures closed = voxelFeatures(cov, m.count);
  const VoxelFeatures iterative = voxelFeatures(cov, m.count, EigenSolver::kIterative);
  ASSERT_TRUE(closed.valid && iterative.valid);
  EXPECT_GT(closed.normal.z(), 0.99);  // sign fixed towards +z
  EXPECT_NEAR((closed.normal - iterative.normal).norm(), 0.0, 1e-9);
  EXPECT_NEAR(closed.planarity, iterative.planarity, 1e-12);
  EXPECT_LT(closed.planarity, 0.1);
  EXPECT_FALSE(voxelFeatures(cov, kMinPointsForFeatures - 1).valid);
  EXPECT_EQ(voxelFeatures(cov, kMinPointsForFeatures - 1).planarity, -1.0);
}

}  // namespace
}  // namespace socc
