// socc/odom/scan_map.hpp: the voxels of clouds merged in parts are those of the clouds together
// (what PosedFrames' target relies on: each kept scan is voxelized once, not at every frame).
#include <gtest/gtest.h>

#include <random>

#include "socc/odom/posed_frames.hpp"
#include "socc/odom/scan_map.hpp"

namespace {

using namespace socc;
using namespace socc::odom;

LabeledCloud randomCloud(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<float> coordinate(-4.f, 4.f);
  std::uniform_int_distribution<int> label(0, kNumClasses - 1);
  LabeledCloud cloud;
  for (std::size_t i = 0; i < n; ++i) {
    cloud.points.emplace_back(coordinate(rng), coordinate(rng), 0.3f * coordinate(rng));
    cloud.labels.push_back(static_cast<std::uint8_t>(label(rng)));
  }
  return cloud;
}

TEST(ScanMap, VoxelsMergedFromPartsAreTheVoxelsOfTheCloudsTogether) {
  std::mt19937 rng(3);
  std::vector<LabeledCloud> clouds;
  std::vector<Eigen::Isometry3d> poses;
  LabeledCloud together;
  for (int k = 0; k < 4; ++k) {
    clouds.push_back(randomCloud(rng, 3000));
    // Quarter turns move the points exactly, however a compiler orders the sums (the voxels'
    // keys and first points are then the same bit for bit; a shift would round them).
    Eigen::Matrix3d quarter_turn;
    quarter_turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int turn = 0; turn < k; ++turn) pose.linear() = quarter_turn * pose.linear();
    poses.push_back(pose);
    appendMoved(clouds.back(), poses.back(), together);
  }
  std::vector<std::vector<CloudVoxel>> parts;
  for (int k = 0; k < 4; ++k) parts.push_back(cloudVoxels(clouds[k], poses[k], 0.5));
  const std::vector<CloudVoxel> merged = mergedVoxels({&parts[0], &parts[1], &parts[2], &parts[3]});
  const std::vector<CloudVoxel> whole = cloudVoxels(together, Eigen::Isometry3d::Identity(), 0.5);

  ASSERT_EQ(merged.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    ASSERT_EQ(merged[i].key, whole[i].key) << i;  // in the order of their first points
    EXPECT_EQ(merged[i].moments.first, whole[i].moments.first) << i;
    EXPECT_EQ(merged[i].moments.count, whole[i].moments.count) << i;
    EXPECT_EQ(merged[i].labels, whole[i].labels) << i;
    EXPECT_NEAR((merged[i].moments.mean() - whole[i].moments.mean()).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR((merged[i].moments.m2() - whole[i].moments.m2()).norm(), 0.0, 1e-9) << i;
  }
  const LocalMap from_parts = buildVoxelMap(merged), from_cloud = buildScanMap(together, 0.5);
  ASSERT_EQ(from_parts.size(), from_cloud.size());
  for (std::size_t i = 0; i < from_cloud.size(); ++i) {
    EXPECT_EQ(from_parts.voxel(i).point, from_cloud.voxel(i).point);
    EXPECT_EQ(from_parts.voxel(i).label, from_cloud.voxel(i).label);
    EXPECT_NEAR(std::abs(from_parts.voxel(i).normal.dot(from_cloud.voxel(i).normal)),
                from_cloud.voxel(i).normal.squaredNorm(), 1e-6);
  }
}

}  // namespace
