// The map keypoints' index behind the search's inlier tests: the nearest keypoint within a
// distance, or none.
#include <gtest/gtest.h>

#include "keypoint_index.hpp"

using socc::localization::KeypointIndex;

namespace {

pcl::PointCloud<pcl::PointNormal>::Ptr cloudOf(std::initializer_list<Eigen::Vector3f> points) {
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
  for (const Eigen::Vector3f& p : points) {
    pcl::PointNormal q;
    q.getVector3fMap() = p;
    q.getNormalVector3fMap() = Eigen::Vector3f::UnitZ();
    cloud->push_back(q);
  }
  return cloud;
}

}  // namespace

TEST(KeypointIndex, FindsTheNearestKeypointWithinTheDistanceOnly) {
  KeypointIndex index(cloudOf({{0.f, 0.f, 0.f}, {2.f, 0.f, 0.f}, {0.f, 5.f, 1.f}}));
  const auto near = index.nearestWithin({1.8f, 0.3f, 0.f}, 1.f);
  ASSERT_TRUE(near);
  EXPECT_EQ(near->index, 1);
  EXPECT_NEAR(near->squared_distance, 0.04f + 0.09f, 1e-6f);
  EXPECT_EQ(index.nearestWithin({0.f, 5.f, 0.2f}, 1.f)->index, 2);
  EXPECT_FALSE(index.nearestWithin({1.f, 2.5f, 0.f}, 1.f));  // 2.24 m from the nearest
}

TEST(KeypointIndex, AnEmptyIndexFindsNothingAndAMovedOneStillFinds) {
  EXPECT_FALSE(KeypointIndex().nearestWithin({0.f, 0.f, 0.f}, 1e6f));
  EXPECT_FALSE(KeypointIndex(cloudOf({})).nearestWithin({0.f, 0.f, 0.f}, 1e6f));
  KeypointIndex index(cloudOf({{0.f, 0.f, 0.f}}));
  const KeypointIndex moved(std::move(index));  // the tree keeps its adaptor on the heap
  EXPECT_EQ(moved.nearestWithin({0.1f, 0.f, 0.f}, 1.f)->index, 0);
}
