// A robot mapping in its own frame (odom_client --own-frame, docs/relocalization.md "Own frame"):
// its kept scans (OwnFrameMap), the merge transform, and its search of the shared map driven by
// its own-frame odometry (Relocalizer::addStacked) against an in-process map: merged into A's map
// frame where A mapped, never elsewhere.
#include <gtest/gtest.h>

#include "closed_loop_harness.hpp"
#include "in_process_map.hpp"
#include "socc/odom/own_frame_map.hpp"
#include "socc/odom/relocalizer.hpp"

namespace {

using namespace socc::odom;
using harness::ClosedLoop;
using harness::InProcessMap;
using harness::simulated;
using harness::smallMapSearch;

// A frame of a few points around the sensor at pose (own frame).
FrameEstimate frameAt(std::int64_t seq, const Eigen::Isometry3d& pose) {
  FrameEstimate f;
  f.seq = seq;
  f.utime = seq * 100'000;
  f.pose = pose;
  for (int i = 0; i < 200; ++i)
    f.cloud.points.emplace_back(static_cast<float>(i % 20) - 10.f, static_cast<float>(i / 20),
                                -1.5f);
  f.cloud.labels.assign(f.cloud.points.size(), 0);
  return f;
}

Eigen::Isometry3d along(double x) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation().x() = x;
  return p;
}

TEST(OwnFrameMap, KeepsAScanEveryFewMetresAndBoundsThem) {
  OwnFrameLimits limits;
  limits.recent_scans = 3;
  limits.keyframe_distance = 2.0;
  limits.max_keyframes = 4;
  OwnFrameMap own(limits);
  EXPECT_EQ(own.target().size(), 0u);
  for (int k = 0; k < 21; ++k) own.add(frameAt(k, along(0.5 * k)));  // 10 m in 0.5 m steps
  EXPECT_EQ(own.frames(), 3u);
  EXPECT_GT(own.target().size(), 0u);
  // Keyframes at 0, 2, ..., 10 m (seq 0, 4, ..., 20): the oldest two dropped beyond 4.
  ASSERT_EQ(own.keyframes().size(), 4u);
  EXPECT_EQ(own.droppedKeyframes(), 2u);
  EXPECT_EQ(own.keyframes().front().seq, 8);
  EXPECT_EQ(own.keyframes().back().seq, 20);
  EXPECT_TRUE(own.newestPose().isApprox(along(10.0)));
  EXPECT_GT(own.keyframeBytes(), 0u);
  EXPECT_GT(own.recentBytes(), 0u);
}

TEST(OwnFrameMap, MergeMovesTheKeptScansInOrderAndEndsWithTheNewestFrame) {
  Eigen::Isometry3d verified = Eigen::Isometry3d::Identity();
  verified.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  verified.translation() = Eigen::Vector3d(40.0, -3.0, 1.0);
  const Eigen::Isometry3d own_pose = along(5.0);
  const Eigen::Isometry3d shared_T_own = sharedFromOwn(verified, own_pose);
  EXPECT_TRUE((shared_T_own * own_pose).isApprox(verified));

  OwnFrameMap own;
  for (int k = 0; k < 10; ++k) own.add(frameAt(k, along(0.5 * k)));
  const OwnKeyframe newest{11, 1'100'000, own_pose, {}};
  const std::vector<OwnKeyframe> merged = mergedKeyframes(own.keyframes(), newest, shared_T_own);
  ASSERT_EQ(merged.size(), own.keyframes().size() + 1);
  for (std::size_t i = 1; i < merged.size(); ++i) {
    EXPECT_LT(merged[i - 1].seq, merged[i].seq);
    EXPECT_LT(merged[i - 1].utime, merged[i].utime);  // the server's plausibility needs it
  }
  EXPECT_TRUE(merged.back().pose.isApprox(verified));
  EXPECT_TRUE(merged.front().pose.isApprox(shared_T_own * own.keyframes().front().pose));
  // The newest frame already kept as the last keyframe is not integrated twice.
  const OwnKeyframe last = own.keyframes().back();
  EXPECT_EQ(mergedKeyframes(own.keyframes(), last, shared_T_own).size(), own.keyframes().size());
}

struct OwnFrameRun {
  int merged_at = -1;                                             // scan of the merge, -1: none
  Eigen::Isometry3d shared_pose = Eigen::Isometry3d::Identity();  // of that scan, merged
};

// A robot driving scans [first, first + scans) of scene in its own frame (identity at first),
// searching map after each scan with its own-frame motion, as OdomRunner does.
OwnFrameRun driveOwnFrame(const OdomConfig& cfg, const socc::sim::Scene& scene, int first,
                          int scans, MapAccess& map) {
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  Odometry odometry(cfg, Eigen::Isometry3d::Identity());
  OwnFrameMap own;
  Relocalizer search(cfg);
  Eigen::Isometry3d searched_at = Eigen::Isometry3d::Identity();
  for (int k = first; k < first + scans; ++k) {
    const PreparedScan scan = prepareScan(cfg, simulated(scene, lidar, k, false), k, k * 100'000);
    const FrameEstimate f = odometry.registerFrame(scan, own.target());
    if (f.held || !f.health.healthy()) continue;
    own.add(f);
    const auto count = static_cast<std::size_t>(cfg.relocalize_stack_scans);
    const Relocalization r = search.addStacked(own.stacked(count, cfg.deskew_reference_time),
                                               static_cast<int>(std::min(count, own.frames())),
                                               searched_at.inverse() * f.pose, map, {});
    searched_at = f.pose;
    if (!r.pose) continue;
    return {k, sharedFromOwn(*r.pose, f.pose) * f.pose};
  }
  return {};
}

TEST(OwnFrame, MergedIntoTheSharedFrameWhereItWasMappedNeverElsewhere) {
  socc::sim::SceneOptions options;
  options.frames = 30;
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  // Robot A maps frames 0-19 from its exact start (the shared frame is the GT frame).
  ClosedLoop a(scene.trajectory.poseAt(0.0));
  for (int k = 0; k < 20; ++k) a.step(simulated(scene, lidar, k, false), k);
  InProcessMap access(a.map, a.cfg, smallMapSearch());

  const OwnFrameRun b = driveOwnFrame(a.cfg, scene, 8, 5, access);
  ASSERT_GE(b.merged_at, 8 + a.cfg.relocalize_confirm_scans - 1) << "not merged, or unconfirmed";
  const Eigen::Isometry3d d =
      a.poses.at(static_cast<std::size_t>(b.merged_at)).inverse() * b.shared_pose;
  std::printf("merged at scan %d: %.3f m, %.3f deg from A's pose\n", b.merged_at,
              d.translation().norm(), Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI);
  EXPECT_LT(d.translation().norm(), 0.1);
  EXPECT_LT(Eigen::AngleAxisd(d.linear()).angle(), 1.0 * M_PI / 180.0);

  socc::sim::SceneOptions other = options;
  other.seed = 99;  // another street: same kind of place, other buildings
  const OwnFrameRun c = driveOwnFrame(a.cfg, socc::sim::buildScene(other), 5, 2, access);
  EXPECT_EQ(c.merged_at, -1) << "merged into a place that is not in the map";
}

}  // namespace
