// Closed-loop odometry with exact ground truth: socc-sim scans (with motion distortion) go
// through the whole client pipeline (prepare, chunk query of the server's own grid, iterated
// deskew + registration, health) and back into that grid, as odom_client and map_server do,
// without the LCM transport. The deskew unit tests check the formula; these check that deskew,
// registration and map converge together across scenes, sensors, speeds and routes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "closed_loop_harness.hpp"

using namespace socc::odom;
using namespace socc::odom::harness;

namespace {

constexpr int kCorridorFrames = 40;

struct Case {
  const char* scene;
  const char* route;
  const char* sensor;
  double speed;  // [m/s]; 0 = the scene's default
  int frames;
  double max_drift;  // [% of the distance travelled] end-point drift allowed
};

std::ostream& operator<<(std::ostream& out, const Case& c) {
  return out << c.scene << '/' << c.route << '/' << c.sensor << '/' << c.speed;
}

class ClosedLoopDistortion : public ::testing::TestWithParam<Case> {};

// Every frame of scene as the sensor sees it with realism's errors and motion distortion.
std::vector<socc::LabeledCloud> simulatedRun(const socc::sim::Scene& scene, const char* sensor,
                                             int frames, const socc::sim::Realism& realism) {
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset(sensor);
  std::vector<socc::LabeledCloud> scans;
  for (int k = 0; k < frames; ++k) scans.push_back(simulated(scene, lidar, k, true, &realism));
  return scans;
}

// The angle between the up directions of an estimated and a true pose [deg].
double tiltErrorDeg(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  const Eigen::Vector3d up_est = estimate.linear().transpose().col(2);
  const Eigen::Vector3d up_true = truth.linear().transpose().col(2);
  return std::acos(std::clamp(up_est.dot(up_true), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST_P(ClosedLoopDistortion, ConvergesAndStaysCloseToGroundTruth) {
  const Case& c = GetParam();
  socc::sim::SceneOptions options;
  options.type = socc::sim::parseSceneType(c.scene);
  options.route = c.route;
  options.frames = static_cast<std::size_t>(c.frames);
  if (c.speed > 0.0) options.speed = c.speed;
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset(c.sensor);
  ClosedLoop loop(scene.trajectory.poseAt(0.0));
  for (int k = 0; k < c.frames; ++k) loop.step(simulated(scene, lidar, k, true), k);

  ASSERT_EQ(loop.poses.size(), static_cast<std::size_t>(c.frames));
  EXPECT_EQ(loop.integrated, c.frames) << "every frame healthy and integrated";
  double travelled = 0.0, worst_step = 0.0;
  for (int k = 1; k < c.frames; ++k) {
    const Eigen::Isometry3d gt_step =
        scene.trajectory.poseAt(0.1 * (k - 1)).inverse() * scene.trajectory.poseAt(0.1 * k);
    const Eigen::Isometry3d est_step = loop.poses[k - 1].inverse() * loop.poses[k];
    travelled += gt_step.translation().norm();
    const double err = (gt_step.inverse() * est_step).translation().norm();
    worst_step = std::max(worst_step, err);
  }
  const Eigen::Isometry3d gt_end = scene.trajectory.poseAt(0.1 * (c.frames - 1));
  const double drift = (gt_end.inverse() * loop.poses.back()).translation().norm();
  std::printf("%s/%s/%s: %.1f m, end drift %.3f m (%.2f %%), worst step error %.3f m\n", c.scene,
              c.route, c.sensor, travelled, drift, 100.0 * drift / travelled, worst_step);
  EXPECT_LT(100.0 * drift / travelled, c.max_drift);
  // The unstable loop's steps were off by 0.4-0.6 m. A sparse sensor's start-up step in the office
  // is up to 0.13 m off (0.15 m true step; the slow-start limit, odom_client/README.md).
  EXPECT_LT(worst_step, 0.15) << "no oscillation of the estimated steps";
}

// Short runs (CI time under ASan): the oscillation the iterated mid-sweep deskew removes used to
// diverge within ~25 frames on every one of these. The 20-22 m/s streets start cold at that
// speed: from "standing still" ICP alone converges to standing still there (first-motion search).
INSTANTIATE_TEST_SUITE_P(
    Space, ClosedLoopDistortion,
    ::testing::Values(Case{"street", "straight", "hdl64", 0.0, 25, 0.5},
                      Case{"street", "straight", "vlp32", 14.0, 25, 1.0},
                      Case{"street", "straight", "vlp32", 22.0, 25, 1.0},  // cold start
                      Case{"street", "straight", "hdl64", 20.0, 20, 0.5},
                      Case{"street", "circle", "vlp16", 9.0, 30, 1.0},
                      Case{"zigzag", "auto", "vlp16", 0.0, 30, 3.0},  // degenerate
                      Case{"indoor", "auto", "vlp32", 0.0, 25, 1.5},  // 1.9 m
                      Case{"office", "auto", "vlp32", 0.0, 30, 1.0}));

// A featureless corridor seen by a sensor with KITTI-like errors (per-laser calibration, range
// noise, body motion): the errors give the walls a texture that moves with the sensor. Nothing
// pins the motion along the corridor, so every frame is flagged degenerate; the odometry coasts
// along it on the motion model and keeps tracking. Registered freely along the axis, the frames
// slid, accelerated and the robot was declared lost (docs/robustness.md, "Degenerate frames").
TEST(ClosedLoop, AFeaturelessCorridorWithSensorErrorsCoastsFlaggedAndKeepsTracking) {
  const socc::sim::Realism realism = socc::sim::realismPreset("kitti");
  socc::sim::SceneOptions options;
  options.type = socc::sim::SceneType::kCorridor;
  options.frames = kCorridorFrames;
  options.body_motion = realism.motion;
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("hdl64");
  OdomConfig cfg;
  cfg.vertical_angle_correction_deg = 0.205;  // odom_client/config/kitti.yaml
  ClosedLoop loop(scene.trajectory.poseAt(0.0), cfg);
  for (int k = 0; k < kCorridorFrames; ++k)
    loop.step(simulated(scene, lidar, k, true, &realism), k);
  EXPECT_EQ(loop.integrated, kCorridorFrames) << "every frame healthy and integrated";
  EXPECT_EQ(loop.tracking.state(), TrackingState::kTracking);
  EXPECT_GE(loop.degenerate, kCorridorFrames - 2) << "flagged (the held first scan's pair may not)";
  // Coasting: the steps along the corridor change little, not by the sensor's texture.
  double worst_change = 0.0;
  for (std::size_t k = 3; k < loop.poses.size(); ++k) {
    const Eigen::Vector3d step = loop.poses[k].translation() - loop.poses[k - 1].translation();
    const Eigen::Vector3d before =
        loop.poses[k - 1].translation() - loop.poses[k - 2].translation();
    worst_change = std::max(worst_change, (step - before).norm());
  }
  std::printf("corridor: worst change of the step %.4f m\n", worst_change);
  // 0.011 m with the prediction worth min_constraint pairs, 0.118 m registered freely.
  EXPECT_LT(worst_change, 0.03) << "3 m/s^2 at 10 Hz";
}

// A street seen by a sensor with KITTI-like errors and its 0.22 deg elevation error left
// uncorrected: the ground turns into a shallow cone that tilts every registration step the same
// way (odom_client/README.md, elevation correction), 0.27 deg in 40 frames. An INS's gravity
// reference (here the true up with the INS's stated sigma) holds the tilt, the more the faster
// the odometry's tilt is said to drift (gravity_tilt_walk_deg: the filter's gain).
TEST(ClosedLoop, AGravityReferenceHoldsTheTiltThatTheScansLetDrift) {
  constexpr int kFrames = 40;
  const socc::sim::Realism realism = socc::sim::realismPreset("kitti");
  socc::sim::SceneOptions options;
  options.frames = kFrames;
  options.body_motion = realism.motion;
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  // Simulated once for the three runs (most of this test's time under the sanitizers).
  const std::vector<socc::LabeledCloud> scans = simulatedRun(scene, "hdl64", kFrames, realism);
  // walk < 0: no reference; else gravity_tilt_walk_deg.
  const auto tiltError = [&](double walk) {
    OdomConfig cfg;
    if (walk >= 0.0) cfg.gravity_tilt_walk_deg = walk;
    ClosedLoop loop(scene.trajectory.poseAt(0.0), cfg);
    for (int k = 0; k < kFrames; ++k) {
      const Eigen::Matrix3d truth = scene.trajectory.poseAt(0.1 * k).linear();
      std::optional<socc::GravityReference> gravity;
      if (walk >= 0.0) gravity = socc::GravityReference{truth.transpose().col(2), 6e-4};
      loop.step(scans[static_cast<std::size_t>(k)], k, gravity);
    }
    EXPECT_EQ(loop.integrated, kFrames);
    return tiltErrorDeg(loop.poses.back(), scene.trajectory.poseAt(0.1 * (kFrames - 1)));
  };
  const double alone = tiltError(-1.0), held = tiltError(OdomConfig{}.gravity_tilt_walk_deg),
               firm = tiltError(0.1);
  std::printf(
      "street, uncorrected elevation error: tilt after %d frames %.4f deg alone, "
      "%.4f deg with the reference (default walk), %.4f deg (walk 0.1)\n",
      kFrames, alone, held, firm);
  EXPECT_LT(held, 0.7 * alone);  // 0.27 -> 0.13 deg
  EXPECT_LT(firm, 0.2 * alone);  // 0.27 -> 0.02 deg
}

// A VLP-16 without semantics whose roll turns 1.5 deg within 1.5 s (a car leaning into a turn)
// on a level street with the preset's sensor errors. Far ground and facade rings have no surface
// normal of their own (one ring per neighbourhood), and point pairs between them and the map's
// sparse voxels hold the sensor at the tilt that made the map: the roll lags (docs/robustness.md
// "Sparse point pairs"). Without those pairs the scans' planes follow it.
TEST(ClosedLoop, ASparseSensorFollowsARollChange) {
  constexpr int kFrames = 30;
  const socc::sim::Realism realism = socc::sim::realismPreset("kitti");
  socc::sim::SceneOptions options;
  options.frames = kFrames;
  options.poses.emplace();
  for (int k = 0; k < kFrames; ++k) {
    const double roll = 1.5 * M_PI / 180.0 * std::clamp((k - 5) / 15.0, 0.0, 1.0);
    Eigen::Isometry3d pose(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
    pose.translation() = Eigen::Vector3d(1.0 * k, 0.0, 0.0);  // 10 m/s
    options.poses->push_back(pose);
  }
  const socc::sim::Scene scene = socc::sim::buildScene(options);
  const std::vector<socc::LabeledCloud> scans = simulatedRun(scene, "vlp16", kFrames, realism);
  // The largest tilt error over the run [deg].
  const auto worstTilt = [&](bool point_pairs) {
    OdomConfig cfg;
    cfg.use_semantics = false;
    cfg.vertical_angle_correction_deg = 0.205;  // the preset's elevation error (config/kitti.yaml)
    cfg.sparse_point_pairs = point_pairs;
    ClosedLoop loop(scene.trajectory.poseAt(0.0), cfg);
    for (int k = 0; k < kFrames; ++k) loop.step(scans[static_cast<std::size_t>(k)], k);
    EXPECT_EQ(loop.integrated, kFrames);
    double worst = 0.0;
    for (std::size_t k = 0; k < loop.poses.size(); ++k)
      worst = std::max(worst, tiltErrorDeg(loop.poses[k], scene.trajectory.poseAt(0.1 * k)));
    return worst;
  };
  const double with_pairs = worstTilt(true), without = worstTilt(false);
  std::printf(
      "VLP-16, 1.5 deg roll in 1.5 s: worst tilt error %.3f deg with sparse point pairs, "
      "%.3f deg without\n",
      with_pairs, without);
  EXPECT_LT(without, 0.6 * with_pairs);
}

// A robot whose scans suddenly come from another place (a kidnapped robot, a wrong sensor
// stream): its frames turn unhealthy, it declares itself lost, and nothing more is integrated.
TEST(ClosedLoop, AKidnappedRobotGetsLostAndStopsIntegrating) {
  socc::sim::SceneOptions here;
  here.frames = 20;
  socc::sim::SceneOptions elsewhere = here;
  elsewhere.type = socc::sim::SceneType::kIndoor;
  const socc::sim::Scene scene = socc::sim::buildScene(here);
  const socc::sim::Scene other = socc::sim::buildScene(elsewhere);
  const socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  ClosedLoop loop(scene.trajectory.poseAt(0.0));
  for (int k = 0; k < 10; ++k) loop.step(simulated(scene, lidar, k, true), k);
  ASSERT_EQ(loop.integrated, 10);
  const std::int64_t version = loop.map.version();
  // Lost after max_unhealthy_frames (5) foreign frames; two more must leave the map alone too.
  for (int k = 10; k < 17; ++k) loop.step(simulated(other, lidar, k, true), k);
  EXPECT_EQ(loop.tracking.state(), TrackingState::kLost);
  EXPECT_EQ(loop.integrated, 10) << "a frame of the other place entered the map";
  EXPECT_EQ(loop.map.version(), version);
}

}  // namespace
