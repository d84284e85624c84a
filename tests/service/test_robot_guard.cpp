// The server protects the shared map (issue 11 item 4): INTEGRATEs whose pose is implausible
// against the robot's last accepted one, or of a robot that reported LOST or RELOCALIZING, are
// refused with FAILED_PRECONDITION and change neither the map nor the robot's pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "service/plausibility.hpp"
#include "service_test_helpers.hpp"
#include "socc/kitti_io.hpp"

namespace socc::service {
namespace {

using test::scan;
using R = robot_status_request_t;

// scan() of robot at seq from (x, y) with heading yaw [deg], taken at t [s].
integrate_request_t scanAt(const std::string& robot, std::int64_t seq, double x, double t,
                           double yaw_deg = 0.0, double y = 0.0) {
  integrate_request_t request = scan(robot, seq, x);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  pose.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).matrix();
  request.sensor_pose = toLcm(pose);
  request.scan_utime = std::llround(t * 1e6);
  return request;
}

// What a refused request must leave alone: map content and version, integrations, the pose.
struct StateBefore {
  explicit StateBefore(const MapService& service, const std::string& robot)
      : content(test::content(service.getChunk(test::everything()))),
        version(service.map().version()),
        integrations(service.integrations()),
        state(*service.robots().find(robot)) {}
  void expectUnchanged(const MapService& service) const {
    EXPECT_EQ(test::content(service.getChunk(test::everything())), content);
    EXPECT_EQ(service.map().version(), version);
    EXPECT_EQ(service.integrations(), integrations);
    const robot_state_t& now = *service.robots().find(state.robot_id);
    EXPECT_EQ(now.last_seq, state.last_seq);
    EXPECT_EQ(now.last_scan_utime, state.last_scan_utime);
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(now.last_pose.translation[i], state.last_pose.translation[i]);
    EXPECT_EQ(now.integrations, state.integrations);
  }
  std::vector<std::uint8_t> content;
  std::int64_t version;
  std::int64_t integrations;
  robot_state_t state;
};

std::int8_t statusOf(const integrate_reply_t& reply) {
  return reply.header.status;
}

TEST(RobotGuard, JumpIsRefusedAndChangesNothing) {
  MapService service(test::smallConfig());
  ASSERT_EQ(statusOf(service.integrate(scanAt("car1", 1, 0.0, 0.1))), +reply_header_t::OK);
  // 20 m/s.
  ASSERT_EQ(statusOf(service.integrate(scanAt("car1", 2, 2.0, 0.2))), +reply_header_t::OK);
  const StateBefore before(service, "car1");

  const integrate_reply_t refused = service.integrate(scanAt("car1", 3, 39.0, 0.3));
  EXPECT_EQ(statusOf(refused), +reply_header_t::FAILED_PRECONDITION);
  EXPECT_EQ(refused.header.message,
            "pose jumps 37.0 m in 0.1 s (370 m/s > max 40 m/s) from robot car1's last accepted "
            "pose (seq 2)");
  EXPECT_FALSE(refused.duplicate);
  EXPECT_EQ(refused.map_version, before.version);
  before.expectUnchanged(service);
  EXPECT_EQ(service.robots().find("car1")->refused_integrations, 1);
  bool truncated = false;
  EXPECT_EQ(service.robots().history("car1", 0, 100, &truncated).num_poses, 2);

  // Judged against the last ACCEPTED pose (seq 2 at 0.2 s), not the refused one.
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 4, 40.0, 0.4))),
            +reply_header_t::FAILED_PRECONDITION);
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 5, 5.0, 0.5))), +reply_header_t::OK);
  EXPECT_EQ(service.robots().find("car1")->last_seq, 5);
  EXPECT_EQ(service.robots().find("car1")->refused_integrations, 2);
}

TEST(RobotGuard, OtherRobotsAreUnaffected) {
  MapService service(test::smallConfig());
  service.integrate(scanAt("car1", 1, 0.0, 0.1));
  service.integrate(scanAt("car2", 1, -3.0, 0.1));
  for (int seq = 2; seq <= 6; ++seq) {
    EXPECT_EQ(statusOf(service.integrate(scanAt("car1", seq, 100.0 * seq, 0.1 * seq))),
              +reply_header_t::FAILED_PRECONDITION);
    EXPECT_EQ(statusOf(service.integrate(scanAt("car2", seq, -3.0 + seq, 0.1 * seq))),
              +reply_header_t::OK);
  }
  EXPECT_EQ(service.robots().find("car2")->integrations, 6);
  EXPECT_EQ(service.robots().find("car2")->refused_integrations, 0);
  EXPECT_EQ(service.robots().find("car1")->integrations, 1);
}

TEST(RobotGuard, TurnsTimestampsAndGaps) {
  MapService service(test::smallConfig());
  service.integrate(scanAt("car1", 1, 0.0, 1.0));
  // 90 deg in 0.1 s.
  const integrate_reply_t turn = service.integrate(scanAt("car1", 2, 0.0, 1.1, 90.0));
  EXPECT_EQ(statusOf(turn), +reply_header_t::FAILED_PRECONDITION);
  EXPECT_EQ(
      turn.header.message.rfind("pose turns 90.0 deg in 0.1 s (900 deg/s > max 360 deg/s)", 0), 0u)
      << turn.header.message;
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 3, 0.5, 1.2, 30.0))), +reply_header_t::OK);
  // Equal or backward scan times: only the slack (0.5 m, 10 deg).
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 4, 0.9, 1.2, 35.0))), +reply_header_t::OK);
  const integrate_reply_t back = service.integrate(scanAt("car1", 5, 2.0, 1.0, 35.0));
  EXPECT_EQ(statusOf(back), +reply_header_t::FAILED_PRECONDITION);
  EXPECT_NE(back.header.message.find("scan_utime does not advance"), std::string::npos)
      << back.header.message;
  // Back after 100 s: 30 m is plausible.
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 6, 20.9, 101.2, 80.0, 22.0))),
            +reply_header_t::OK);
}

TEST(RobotGuard, FirstIntegrationIsAlwaysAcceptedAndTheGateCanBeOff) {
  ServerConfig config = test::smallConfig();
  MapService service(config);
  EXPECT_EQ(statusOf(service.integrate(scanAt("far", 1, 30.0, 0.0, 170.0))), +reply_header_t::OK);
  config.plausibility.enabled = false;
  MapService open(config);
  open.integrate(scanAt("car1", 1, 0.0, 0.1));
  EXPECT_EQ(statusOf(open.integrate(scanAt("car1", 2, 30.0, 0.2))), +reply_header_t::OK);
}

TEST(RobotGuard, LimitsFromTheServerConfig) {
  // The shipped file states the defaults.
  const auto shipped = std::filesystem::path(__FILE__).parent_path() / "../../map_server/config";
  const PlausibilityLimits defaults;
  const PlausibilityLimits read = loadServerConfig(shipped / "server.yaml").plausibility;
  EXPECT_EQ(read.enabled, defaults.enabled);
  EXPECT_EQ(read.max_linear_speed, defaults.max_linear_speed);
  EXPECT_EQ(read.max_angular_speed, defaults.max_angular_speed);
  EXPECT_EQ(read.linear_slack, defaults.linear_slack);
  EXPECT_EQ(read.angular_slack, defaults.angular_slack);

  test::TempDir dir;
  const auto load = [&](const std::string& text) {
    std::ofstream(dir.path() / "server.yaml") << text;
    return loadServerConfig(dir.path() / "server.yaml").plausibility;
  };
  const PlausibilityLimits set = load(
      "plausibility:\n  enabled: false\n  max_linear_speed: 5\n  max_angular_speed: 90\n"
      "  linear_slack: 0\n  angular_slack: 2.5\n");
  EXPECT_FALSE(set.enabled);
  EXPECT_EQ(set.max_linear_speed, 5.0);
  EXPECT_EQ(set.max_angular_speed, 90.0);
  EXPECT_EQ(set.linear_slack, 0.0);
  EXPECT_EQ(set.angular_slack, 2.5);
  for (const char* bad :
       {"plausibility:\n  max_linear_speed: 0\n", "plausibility:\n  linear_slack: -1\n",
        "plausibility:\n  speed: 3\n", "plausibility:\n  enabled: maybe\n", "plausibility: 3\n"})
    EXPECT_THROW(load(bad), std::runtime_error) << bad;
}

TEST(RobotGuard, ImplausibleMotionLimits) {
  const PlausibilityLimits limits;  // 40 m/s + 0.5 m, 360 deg/s + 10 deg
  const pose3d_t origin = toLcm(Eigen::Isometry3d::Identity());
  pose3d_t moved = origin;
  moved.translation[0] = 4.4;
  EXPECT_EQ(implausibleMotion(origin, 0, moved, 100'000, limits), "");
  moved.translation[0] = 4.6;
  EXPECT_NE(implausibleMotion(origin, 0, moved, 100'000, limits), "");
  // Overflowing time differences stay defined.
  EXPECT_EQ(implausibleMotion(origin, INT64_MIN, moved, INT64_MAX, limits), "");
  EXPECT_NE(implausibleMotion(origin, INT64_MAX, moved, INT64_MIN, limits), "");
}

TEST(RobotGuard, DefaultLimitsAcceptEveryKittiTrajectory) {
  // Real cars at 10 Hz: up to 27.4 m/s (seq 01) and 48 deg/s (seq 00).
  const std::filesystem::path gt = std::filesystem::path(SOCC_SHARED_DATA_DIR) / "kitti_gt";
  if (!std::filesystem::exists(gt / "poses" / "00.txt"))
    GTEST_SKIP() << "no KITTI ground truth in " << gt;
  const PlausibilityLimits limits;
  for (int seq = 0; seq <= 10; ++seq) {
    char name[16];
    std::snprintf(name, sizeof(name), "%02d.txt", seq);
    // seq 03's calibration is not in the data folder: camera frame
    const Poses poses =
        seq == 3 ? readKittiPoses(gt / "poses" / name) : readKittiGtLidarPoses(gt, seq);
    for (std::size_t i = 1; i < poses.size(); ++i)
      ASSERT_EQ(implausibleMotion(toLcm(poses[i - 1]), static_cast<std::int64_t>(i - 1) * 100'000,
                                  toLcm(poses[i]), static_cast<std::int64_t>(i) * 100'000, limits),
                "")
          << "KITTI " << name << " frame " << i;
  }
}

TEST(RobotGuard, TrackingReportIsStoredAndShownInStats) {
  MapService service(test::smallConfig());
  const robot_status_reply_t unknown =
      service.robotStatus(test::trackingReport("car1", R::LOST, 0));
  EXPECT_EQ(unknown.header.status, +reply_header_t::NOT_FOUND);
  service.integrate(scanAt("car1", 1, 0.0, 0.1));
  const robot_status_reply_t reply =
      service.robotStatus(test::trackingReport("car1", R::DEGRADED, 1, "3 unhealthy frames"));
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_EQ(reply.state.tracking_state, +R::DEGRADED);
  const map_stats_t stats = service.stats({});
  ASSERT_EQ(stats.robots.size(), 1u);
  EXPECT_EQ(stats.robots[0].tracking_state, +R::DEGRADED);
  EXPECT_EQ(stats.robots[0].tracking_reason, "3 unhealthy frames");
  EXPECT_EQ(stats.robots[0].tracking_seq, 1);
  EXPECT_EQ(stats.robots[0].tracking_utime, 100000);
  // DEGRADED robots still integrate (the client decides frame by frame).
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 2, 1.0, 0.2))), +reply_header_t::OK);

  for (auto bad : {test::trackingReport("car1", 4, 2), test::trackingReport("car1", -1, 2),
                   test::trackingReport("car1", R::LOST, -1),
                   test::trackingReport("car1", R::LOST, 2, "line\nbreak"),
                   test::trackingReport("car1", R::LOST, 2, std::string(201, 'x'))})
    EXPECT_EQ(service.robotStatus(bad).header.status, +reply_header_t::INVALID_ARGUMENT);
  EXPECT_EQ(service.robots().find("car1")->tracking_state, +R::DEGRADED);
}

TEST(RobotGuard, LostRobotIsRefusedUntilItTracksAgain) {
  MapService service(test::smallConfig());
  service.integrate(scanAt("car1", 1, 0.0, 0.1));
  service.integrate(scanAt("car2", 1, 5.0, 0.1));
  for (const std::int8_t state : {R::LOST, R::RELOCALIZING}) {
    ASSERT_EQ(
        service.robotStatus(test::trackingReport("car1", state, 1, "12 bad frames")).header.status,
        +reply_header_t::OK);
    const StateBefore before(service, "car1");
    const integrate_reply_t refused = service.integrate(scanAt("car1", 2, 0.1, 0.2));
    EXPECT_EQ(statusOf(refused), +reply_header_t::FAILED_PRECONDITION);
    EXPECT_NE(refused.header.message.find("robot car1 reported"), std::string::npos);
    EXPECT_NE(refused.header.message.find("(12 bad frames)"), std::string::npos);
    before.expectUnchanged(service);
    EXPECT_EQ(statusOf(service.integrate(
                  scanAt("car2", service.robots().find("car2")->last_seq + 1, 5.0, 0.2))),
              +reply_header_t::OK);
  }
  // Relocalized: its next pose starts anew, however far from the one before it was lost ...
  ASSERT_EQ(service.robotStatus(test::trackingReport("car1", R::TRACKING, 9)).header.status,
            +reply_header_t::OK);
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 10, 25.0, 0.3))), +reply_header_t::OK);
  // ... and is the reference again after that.
  EXPECT_EQ(statusOf(service.integrate(scanAt("car1", 11, 0.0, 0.4))),
            +reply_header_t::FAILED_PRECONDITION);
  EXPECT_EQ(service.robots().find("car1")->refused_integrations, 3);
}

TEST(RobotGuard, TrackingStateSurvivesASnapshot) {
  test::TempDir dir;
  MapService service(test::smallConfig(dir.path()));
  service.integrate(scanAt("car1", 1, 0.0, 0.1));
  service.robotStatus(test::trackingReport("car1", R::LOST, 1, "diverged"));
  service.integrate(scanAt("car1", 2, 0.0, 0.2));
  service.saveSnapshot(dir.path() / "map.snap");
  MapService restored(test::smallConfig(dir.path()));
  restored.loadSnapshot(dir.path() / "map.snap");
  const robot_state_t& state = *restored.robots().find("car1");
  EXPECT_EQ(state.tracking_state, +R::LOST);
  EXPECT_EQ(state.tracking_reason, "diverged");
  EXPECT_EQ(state.refused_integrations, 1);
  EXPECT_EQ(statusOf(restored.integrate(scanAt("car1", 3, 0.0, 0.3))),
            +reply_header_t::FAILED_PRECONDITION);
}

}  // namespace
}  // namespace socc::service
