// ScanStack (relocalization's accumulated cloud, docs/relocalization.md): the scans of a robot
// that does not know where it is, registered onto each other by its own odometry and stacked in
// the newest scan's frame.
#include <gtest/gtest.h>

#include <random>

#include "closed_loop_harness.hpp"
#include "socc/odom/scan_map.hpp"
#include "socc/odom/scan_stack.hpp"

namespace {

using namespace socc::odom;

struct StackWorld {
  socc::sim::Scene scene;
  socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp16");
  OdomConfig cfg;

  explicit StackWorld(socc::sim::SceneType type) : scene(build(type)) {}
  static socc::sim::Scene build(socc::sim::SceneType type) {
    socc::sim::SceneOptions options;
    options.type = type;
    options.frames = 20;
    return socc::sim::buildScene(options);
  }
  PreparedScan scan(int frame) const {
    return prepareScan(cfg, harness::simulated(scene, lidar, frame, false), frame,
                       static_cast<std::int64_t>(frame) * 100000);
  }
};

TEST(ScanStack, FollowsTheRobotsMotionAndKeepsTheLastScans) {
  const StackWorld street(socc::sim::SceneType::kStreet);
  ScanStack stack(street.cfg, 3);
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(stack.add(street.scan(k))) << "frame " << k;
    EXPECT_EQ(stack.size(), static_cast<std::size_t>(std::min(k + 1, 3)));
    if (k == 0) continue;
    const Eigen::Isometry3d truth = street.scene.trajectory.poseAt(0.1 * (k - 1)).inverse() *
                                    street.scene.trajectory.poseAt(0.1 * k);
    const Eigen::Isometry3d error = truth.inverse() * stack.lastMotion();
    EXPECT_LT(error.translation().norm(), 0.05) << "frame " << k;
    EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 0.01) << "frame " << k;
  }
  // The stacked cloud is in the newest scan's frame, as that scan's own points are.
  const PreparedScan stacked = stack.cloud();
  EXPECT_EQ(stacked.seq, 4);
  EXPECT_FALSE(stacked.cloud.hasTimes());
  const PreparedScan newest = street.scan(4);
  EXPECT_GT(stacked.cloud.size(), 0u);
  const LocalMap own = buildScanMap(newest.cloud, 0.5);
  EXPECT_GT(fractionNearMap(stacked.cloud.points, own, Eigen::Isometry3d::Identity(), 0.5), 0.7);
}

// A scan its odometry cannot register (here: points scattered at random, nothing like the
// street) starts the stack over from that scan.
TEST(ScanStack, StartsOverWhenTheOdometryFails) {
  const StackWorld street(socc::sim::SceneType::kStreet);
  ScanStack stack(street.cfg, 5);
  for (int k = 0; k < 3; ++k) stack.add(street.scan(k));
  EXPECT_FALSE(stack.restarted());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coordinate(-30.f, 30.f);
  socc::LabeledCloud noise;
  for (int i = 0; i < 20000; ++i)
    noise.points.emplace_back(coordinate(rng), coordinate(rng), 0.1f * coordinate(rng));
  EXPECT_FALSE(stack.add(prepareScan(street.cfg, noise, 3, 300000)));
  EXPECT_TRUE(stack.restarted());
  EXPECT_EQ(stack.size(), 1u);
  EXPECT_TRUE(stack.lastMotion().isApprox(Eigen::Isometry3d::Identity()));
}

}  // namespace
