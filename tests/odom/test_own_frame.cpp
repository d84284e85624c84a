// A robot mapping in its own frame (odom_client --own-frame, docs/relocalization.md "Own frame"):
// its kept scans (OwnFrameMap), the merge transform, and its search of the shared map driven by
// its own-frame odometry (Relocalizer::addStacked) against an in-process map: merged into A's map
// frame where A mapped, never elsewhere.
#include <gtest/gtest.h>

#include "closed_loop_harness.hpp"
#include "in_process_map.hpp"
#include "socc/odom/kept_place_sweep.hpp"
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
  // Keyframes at 0, 2, 4, 6, 8 m (seq 0, 4, ..., 16): beyond 4, every other one dropped and the
  // spacing doubled, so the path from its start is still kept (0, 4, 8 m), and 10 m is not one.
  ASSERT_EQ(own.keyframes().size(), 3u);
  EXPECT_EQ(own.droppedKeyframes(), 2u);
  EXPECT_DOUBLE_EQ(own.keyframeDistance(), 4.0);
  EXPECT_EQ(own.keyframes().front().seq, 0);
  EXPECT_EQ(own.keyframes()[1].seq, 8);
  EXPECT_EQ(own.keyframes().back().seq, 16);
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
  const std::vector<OwnKeyframe> merged =
      mergedKeyframes(own.keyframes(), newest, FrameBridge(shared_T_own));
  ASSERT_EQ(merged.size(), own.keyframes().size() + 1);
  for (std::size_t i = 1; i < merged.size(); ++i) {
    EXPECT_LT(merged[i - 1].seq, merged[i].seq);
    EXPECT_LT(merged[i - 1].utime, merged[i].utime);  // the server's plausibility needs it
  }
  EXPECT_TRUE(merged.back().pose.isApprox(verified));
  EXPECT_TRUE(merged.front().pose.isApprox(shared_T_own * own.keyframes().front().pose));
  // The newest frame already kept as the last keyframe is not integrated twice.
  const OwnKeyframe last = own.keyframes().back();
  EXPECT_EQ(mergedKeyframes(own.keyframes(), last, FrameBridge(shared_T_own)).size(),
            own.keyframes().size());
}

TEST(KeptPlaceSweep, WalksPairsOfWindowsSkipsTheGapAndStartsAgain) {
  OwnFrameMap own;
  for (int k = 0; k <= 60; ++k) own.add(frameAt(k, along(0.5 * k)));  // kept every 2 m: 16
  ASSERT_EQ(own.keyframes().size(), 16u);
  KeptPlaceSweep sweep(2, 4.0);  // windows of 2 kept scans; 4 m skipped after each pair
  std::vector<std::int64_t> searched;
  std::vector<bool> starts;
  for (int i = 0; i < 6; ++i) {
    const std::optional<KeptPlaceSearch> s = sweep.next(own, 0.0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->scans, 2);
    EXPECT_DOUBLE_EQ(static_cast<double>(s->stacked.seq), s->own_pose.translation().x() / 0.5);
    searched.push_back(s->stacked.seq);
    starts.push_back(s->sweep_start);
    if (i == 1) {  // from the pair's first window's newest scan (2 m) to this one's (6 m)
      EXPECT_TRUE(s->motion.isApprox(along(4.0)));
    }
  }
  // Kept scans 0-1 and 2-3 (a pair), 4 m skipped, 6-7 and 8-9, then 12-13; 14-15 is the forward
  // search's window, so the sweep starts again from the oldest.
  EXPECT_EQ(searched, (std::vector<std::int64_t>{4, 12, 28, 36, 52, 4}));
  EXPECT_EQ(starts, (std::vector<bool>{true, false, false, false, false, true}));

  // A place in the map is followed window by window: no gap after the pair.
  KeptPlaceSweep following(2, 4.0);
  following.next(own, 0.0);
  following.next(own, 0.0);
  EXPECT_EQ(following.next(own, 0.0, true)->stacked.seq, 20);  // kept scans 4-5

  OwnFrameMap few;
  for (int k = 0; k <= 8; ++k) few.add(frameAt(k, along(0.5 * k)));  // 3 kept scans
  EXPECT_FALSE(KeptPlaceSweep(2, 4.0).next(few, 0.0)) << "only the forward search's window";
}

TEST(FrameBridge, EachPlacementHoldsAtItsScanAndTheDriftIsSpreadByPath) {
  // 100 scans: 1 m apart for the first 50, 3 m apart after (the path, not the seq, spreads it).
  std::vector<std::int64_t> seqs;
  std::vector<Eigen::Vector3d> positions;
  for (int k = 0; k < 100; ++k) {
    seqs.push_back(k);
    positions.emplace_back(k < 50 ? k : 50 + 3.0 * (k - 50), 0.0, 0.0);
  }
  const Eigen::Isometry3d from = along(10.0);
  Eigen::Isometry3d to = along(12.0);  // 2 m of drift between the placements
  to.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const FrameBridge bridge(seqs, positions, 20, from, 80, to);
  EXPECT_TRUE(bridge.at(0).isApprox(from));
  EXPECT_TRUE(bridge.at(20).isApprox(from));
  EXPECT_TRUE(bridge.at(80).isApprox(to));
  EXPECT_TRUE(bridge.at(99).isApprox(to));
  // Scan 50 is 30 m along the 120 m between them (20 -> 50 at 1 m, 50 -> 80 at 3 m).
  EXPECT_NEAR(bridge.at(50).translation().x(), 10.0 + 2.0 * 30.0 / 120.0, 1e-9);
  EXPECT_NEAR(bridge.bridgedPath(), 120.0, 1e-9);
  EXPECT_GT(bridge.bridgedDrift(), 2.0);  // the 2 m and the turn's lever at 140 m
  const FrameBridge one(to);
  EXPECT_TRUE(one.at(0).isApprox(to));
  EXPECT_DOUBLE_EQ(one.bridgedPath(), 0.0);
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

// The kept scans of a robot that drove scans [first, first + scans) of scene in its own frame.
OwnFrameMap keptScans(const OdomConfig& cfg, const socc::sim::Scene& scene, int first, int scans) {
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  Odometry odometry(cfg, Eigen::Isometry3d::Identity());
  OwnFrameLimits limits;
  limits.keyframe_distance = 1.0;
  OwnFrameMap own(limits);
  for (int k = first; k < first + scans; ++k) {
    const PreparedScan scan = prepareScan(cfg, simulated(scene, lidar, k, false), k, k * 100'000);
    const FrameEstimate f = odometry.registerFrame(scan, own.target());
    if (!f.held && f.health.healthy()) own.add(f);
  }
  return own;
}

// One sweep of own's kept scans through the search, as OdomRunner looks back: the first place
// confirmed (seq of its kept scan, and that scan's pose in map's frame), or seq -1.
OwnFrameRun lookBack(const OdomConfig& cfg, const OwnFrameMap& own, MapAccess& map) {
  KeptPlaceSweep sweep(2, 0.0);
  Relocalizer search(cfg);
  for (bool first = true;; first = false) {
    const std::optional<KeptPlaceSearch> s = sweep.next(own, cfg.deskew_reference_time);
    if (!s || (s->sweep_start && !first)) return {};
    const Relocalization r = search.addStacked(s->stacked, s->scans, s->motion, map, {});
    if (r.pose)
      return {static_cast<int>(s->stacked.seq), sharedFromOwn(*r.pose, s->own_pose) * s->own_pose};
  }
}

TEST(OwnFrame, LookingBackItFindsAPlaceAnotherRobotMappedAfterItPassed) {
  socc::sim::SceneOptions options;
  options.frames = 30;
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  const OdomConfig cfg;
  // Robot B passed scans 0-19 in its own frame while the map was empty; robot A mapped them after
  // (its map is searched only now: B's newest scans are not in it, its kept ones are).
  const OwnFrameMap b = keptScans(cfg, scene, 0, 20);
  ClosedLoop a(scene.trajectory.poseAt(0.0));
  for (int k = 0; k < 20; ++k) a.step(simulated(scene, lidar, k, false), k);
  InProcessMap access(a.map, a.cfg, smallMapSearch());

  const OwnFrameRun found = lookBack(cfg, b, access);
  ASSERT_GE(found.merged_at, 0) << "no kept place found";
  const Eigen::Isometry3d d =
      a.poses.at(static_cast<std::size_t>(found.merged_at)).inverse() * found.shared_pose;
  std::printf("kept scan %d of %zu found: %.3f m, %.3f deg from A's pose\n", found.merged_at,
              b.keyframes().size(), d.translation().norm(),
              Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI);
  EXPECT_LT(d.translation().norm(), 0.1);
  EXPECT_LT(Eigen::AngleAxisd(d.linear()).angle(), 1.0 * M_PI / 180.0);

  socc::sim::SceneOptions other = options;
  other.seed = 99;  // another street: its kept scans are nowhere in A's map
  EXPECT_EQ(lookBack(cfg, keptScans(cfg, socc::sim::buildScene(other), 0, 12), access).merged_at,
            -1);
}

}  // namespace
