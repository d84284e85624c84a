// Odometry edges that do not see the shared map (docs/consistency.md): a keyframe pair whose
// integrated relative pose holds a jump its scans do not show (the client snapped onto the old
// map) is measured scan to scan, so a revisit's closure contradicts the chain and the graph
// spreads the loop's error over it instead of keeping it.
#include <gtest/gtest.h>

#include <cmath>

#include "consistency_service.hpp"
#include "odometry_edge.hpp"
#include "socc/odom/relocalization.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/scene.hpp"

namespace socc::consistency {
namespace {

constexpr double kLapSpeed = 18.0;  // [m/s] on a 50 m circle: 175 frames a lap
constexpr int kLapStep = 4;         // every 4th frame is sent (7.2 m apart: each one a keyframe)
constexpr double kHeadingDrift = 0.02;

struct SnapDrive {
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::vector<LabeledCloud> scans;
};

// A VLP-32 on socc-sim's circular street, sent every kLapStep frames; the odometry turns 2 % too
// much until keyframe snap_at, where it snaps back onto the truth (as a client does that
// registers against the old walls of the map it drew at the start of the lap).
SnapDrive snapDrive(int frames, int snap_at, int columns = 1800) {
  sim::SceneOptions options;
  options.type = sim::SceneType::kStreet;
  options.route = "circle";
  options.frames = static_cast<std::size_t>(frames);
  options.seed = 1;
  options.speed = kLapSpeed;
  const sim::Scene scene = sim::buildScene(options);
  sim::LidarModel lidar = sim::lidarPreset("vlp32");
  lidar.columns = columns;
  SnapDrive d;
  for (int k = 0; k < frames; k += kLapStep) {
    const double t = k * 0.1;
    d.truth.push_back(scene.trajectory.poseAt(t));
    LabeledCloud cloud;
    cloud.points = sim::simulateScan(scene, lidar, t, static_cast<std::uint64_t>(k), {}).points;
    d.scans.push_back(std::move(cloud));
  }
  d.odometry.push_back(d.truth[0]);
  for (std::size_t i = 1; i < d.truth.size(); ++i) {
    Eigen::Isometry3d rel = d.truth[i - 1].inverse() * d.truth[i];
    const double yaw = std::atan2(rel.linear()(1, 0), rel.linear()(0, 0));
    rel.linear() = Eigen::AngleAxisd(yaw * (1.0 + kHeadingDrift), Eigen::Vector3d::UnitZ()) *
                   rel.linear() * Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ());
    d.odometry.push_back(static_cast<int>(i) >= snap_at ? d.truth[i] : d.odometry.back() * rel);
  }
  return d;
}

Keyframe keyframeOf(const SnapDrive& d, std::size_t i, const Eigen::Isometry3d& pose) {
  Keyframe k;
  k.id = static_cast<int>(i);
  k.seq = static_cast<std::int64_t>(i);
  k.odom_pose = pose;
  k.points = odom::localizationPoints(d.scans[i], ConsistencyParams{}.keyframe_voxel, 60'000);
  return k;
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}

TEST(OdometryEdge, AJumpTheScansDoNotShowIsMeasuredScanToScan) {
  const SnapDrive d = snapDrive(12, 1000);
  const Eigen::Isometry3d truth = d.truth[1].inverse() * d.truth[2];
  const Eigen::Isometry3d motion = d.truth[0].inverse() * d.truth[1];
  const Keyframe previous = keyframeOf(d, 1, d.truth[1]);
  // 1.5 m sideways and 4 deg in the integrated pose: far beyond the integrated edge's noise.
  const Eigen::Isometry3d jump =
      Eigen::Translation3d(0.3, 1.5, 0.0) * Eigen::AngleAxisd(0.07, Eigen::Vector3d::UnitZ());
  const Keyframe snapped = keyframeOf(d, 2, d.truth[2] * jump);
  const ConsistencyParams params;
  OdometryEdgeCheck check;
  const PoseEdge edge =
      odometryEdge(previous, snapped, 7.2, motion, params, map::MapConfig{}, {}, &check);
  ASSERT_TRUE(check.registered);
  EXPECT_TRUE(check.snap);
  EXPECT_LT(translationError(edge.relative, truth), 0.1);
  EXPECT_LT(Eigen::AngleAxisd((edge.relative.inverse() * truth).linear()).angle(), 0.01);
  std::cerr << "snap of " << check.jump_t << " m, " << check.jump_r << " rad found in "
            << check.seconds << " s; scan-to-scan error " << translationError(edge.relative, truth)
            << " m\n";

  // No jump: the integrated edge stays, as measured.
  const Keyframe smooth = keyframeOf(d, 2, d.truth[2]);
  const PoseEdge kept =
      odometryEdge(previous, smooth, 7.2, motion, params, map::MapConfig{}, {}, &check);
  EXPECT_TRUE(check.registered);
  EXPECT_FALSE(check.snap);
  EXPECT_LT(check.jump_t, params.snap_min_t);
  EXPECT_TRUE(kept.relative.isApprox(truth, 1e-9));

  // A tilt alone (1 deg of pitch: the noise of the two measurements in roll and pitch reaches
  // 0.8 deg on the realistic preset) is no snap: the integrated edge stays.
  const Keyframe tilted =
      keyframeOf(d, 2, d.truth[2] * Eigen::AngleAxisd(0.0175, Eigen::Vector3d::UnitY()));
  const PoseEdge untouched =
      odometryEdge(previous, tilted, 7.2, motion, params, map::MapConfig{}, {}, &check);
  EXPECT_TRUE(check.registered);
  EXPECT_GT(check.jump_r, params.snap_min_r);
  EXPECT_FALSE(check.snap);
  EXPECT_TRUE(untouched.relative.isApprox(d.truth[1].inverse() * tilted.odom_pose, 1e-9));

  // A predecessor kept as a pose only (no scan): the integrated edge, unchecked.
  Keyframe pose_only = previous;
  pose_only.points.clear();
  const PoseEdge unchecked =
      odometryEdge(pose_only, snapped, 7.2, motion, params, map::MapConfig{}, {}, &check);
  EXPECT_FALSE(check.checked);
  EXPECT_TRUE(unchecked.relative.isApprox(d.truth[1].inverse() * d.truth[2] * jump, 1e-9));
}

double keyframeAte(const ConsistencyService& service, const SnapDrive& d, bool optimized) {
  double sum = 0.0;
  int n = 0;
  for (const auto& k : service.keyframePoses()) {
    const Eigen::Isometry3d& pose = optimized ? k.optimized : k.odom_pose;
    sum +=
        (pose.translation() - d.truth[static_cast<std::size_t>(k.seq)].translation()).squaredNorm();
    ++n;
  }
  return n == 0 ? 0.0 : std::sqrt(sum / n);
}

TEST(OdometryEdge, ASnapAtTheRevisitIsSpreadOverTheLoopInsteadOfKept) {
  // 1.1 laps; the odometry snaps back onto the truth at the first keyframe of the second lap.
  // With a closure there the snap is measured scan to scan; without one it stays integrated.
  constexpr int kFrames = 196;
  // 900 columns (0.4 deg, denser than the 0.4 m keyframe grid up to 57 m): half the rays to
  // simulate (the test's cost under ASan).
  const SnapDrive d = snapDrive(kFrames, 175 / kLapStep + 1, 900);
  ConsistencyParams params;
  params.keyframe_distance = 6.0;
  params.closure_spacing = 40.0;  // one closure at the revisit: fewer verifications (cost)
  params.correct_grid = false;    // keyframe poses only: no rebuild scans, no rebuilds
  const auto run = [&](bool scan_to_scan, double& before, double& after) {
    params.scan_to_scan_edges = scan_to_scan;
    ConsistencyService service(params, map::MapConfig{});
    for (std::size_t i = 0; i < d.scans.size(); ++i)
      service.observe("car", static_cast<std::int64_t>(i), static_cast<std::int64_t>(i) * 400000,
                      d.odometry[i], d.scans[i]);
    service.flush();
    before = keyframeAte(service, d, false);
    after = keyframeAte(service, d, true);
    return service.stats();
  };
  double kept_before = 0.0, kept_after = 0.0, spread_before = 0.0, spread_after = 0.0;
  const ConsistencyStats kept = run(false, kept_before, kept_after);
  const ConsistencyStats spread = run(true, spread_before, spread_after);
  // Integrated edges only: the closures at the revisit agree with the snapped chain; only the
  // few that reach back into the drifted end of the first lap pull on it (3.8 -> 1.8 m).
  ASSERT_GE(kept.recognition.verified, 1);
  // Scan to scan: the snap is found and the error is spread over the loop.
  EXPECT_GE(spread.odometry_edges.snaps, 1);
  EXPECT_LE(spread.odometry_edges.snaps, 2);  // the drift itself (2 % of the turn) is no snap
  EXPECT_EQ(spread.odometry_edges.checked, spread.keyframes - 1);
  ASSERT_GE(spread.recognition.verified, 1);
  EXPECT_LT(spread_after, kept_after / 3.0);
  EXPECT_EQ(spread.odometry_edges.snaps_unclosed, 0) << "the snapped keyframe closes at once";
  // No closure possible: the snap falls back to its integrated edge, so the graph keeps the
  // revisit the client's snap made (the chain as integrated) instead of losing it.
  params.min_loop_travel = 1e9;
  double unclosed_before = 0.0, unclosed_after = 0.0;
  const ConsistencyStats unclosed = run(true, unclosed_before, unclosed_after);
  EXPECT_EQ(unclosed.recognition.verified, 0);
  EXPECT_GE(unclosed.odometry_edges.snaps, 1);
  EXPECT_EQ(unclosed.odometry_edges.snaps_unclosed, unclosed.odometry_edges.snaps);
  EXPECT_NEAR(unclosed_after, unclosed_before, 1e-6);
  std::cerr << "keyframe ATE " << kept_before << " m: integrated edges -> " << kept_after
            << " m, scan-to-scan where snapped -> " << spread_after << " m; "
            << spread.odometry_edges.snaps << " snaps in " << spread.odometry_edges.checked
            << " edges (" << spread.odometry_edges.registered << " registered), "
            << spread.odometry_edges.seconds / spread.odometry_edges.checked << " s per edge\n";
}

}  // namespace
}  // namespace socc::consistency
