#include <gtest/gtest.h>

#include <cmath>

#include "socc/odom/deskew.hpp"
#include "socc/odom/file_name_stamps.hpp"
#include "socc/odom/frame_health.hpp"
#include "socc/odom/frame_period.hpp"
#include "socc/odom/point_times.hpp"
#include "socc/odom/tracking_state.hpp"

using namespace socc::odom;

namespace {
RegistrationResult result(int correspondences, double rms, const Vector6d& information_diag) {
  RegistrationResult r;
  r.planar = correspondences;
  r.rms_residual = rms;
  r.information = information_diag.asDiagonal();
  r.planar_information = r.information;
  return r;
}
}  // namespace

TEST(FrameHealth, JudgesInliersResidualAndDegeneracy) {
  const OdomConfig cfg;
  const Vector6d ones = Vector6d::Constant(100.0);  // 100 planar pairs pin every direction
  FrameHealth h = judgeRegistration(result(900, 0.1, ones), 1000, 0.5, cfg);
  EXPECT_TRUE(h.healthy()) << h.problem;
  EXPECT_DOUBLE_EQ(h.inlier_fraction, 0.9);
  EXPECT_DOUBLE_EQ(h.residual_ratio, 0.2);
  EXPECT_FALSE(h.degenerate);

  h = judgeRegistration(result(50, 0.1, ones), 1000, 0.5, cfg);
  EXPECT_NE(h.problem.find("inlier fraction"), std::string::npos) << h.problem;
  h = judgeRegistration(result(900, 0.9, ones), 1000, 0.5, cfg);
  EXPECT_NE(h.problem.find("residual"), std::string::npos) << h.problem;

  // A corridor: nothing constrains the translation along its axis. Flagged, still healthy.
  h = judgeRegistration(result(900, 0.1, (Vector6d() << 1e-5, 1, 1, 1, 1, 1).finished()), 1000, 0.5,
                        cfg);
  EXPECT_TRUE(h.degenerate);
  EXPECT_TRUE(h.healthy());
  EXPECT_LT(h.weakest_constraint, 1e-4);
  EXPECT_NEAR(std::abs(h.weakest_direction.x()), 1.0, 1e-9);  // along the corridor
}

// Issue 27: a kinematic limit exceeded is reported, never unhealthy alone (the frame period may be
// a guess, the robot may move as no limit foresaw); with a degenerate registration it is.
TEST(FrameHealth, KinematicSurprisesAreReportedNotUnhealthy) {
  const OdomConfig cfg;  // 40 m/s, 360 deg/s, 20 m/s^2, 720 deg/s^2
  const Vector6d cruise = (Vector6d() << 10, 0, 0, 0, 0, 0.2).finished();
  FrameHealth h;
  judgeMotion(h, cruise, &cruise, 0.1, cfg);
  EXPECT_TRUE(h.healthy()) << h.problem;
  EXPECT_TRUE(h.surprise.empty()) << h.surprise;
  EXPECT_DOUBLE_EQ(h.linear_speed, 10.0);

  const auto surprise = [&cfg, &cruise](const Vector6d& twist, const Vector6d* previous) {
    FrameHealth good;
    judgeMotion(good, twist, previous, 0.1, cfg);
    EXPECT_TRUE(good.healthy()) << good.problem;
    return good.surprise;
  };
  EXPECT_NE(surprise((Vector6d() << 60, 0, 0, 0, 0, 0).finished(), nullptr).find("speed"),
            std::string::npos);
  EXPECT_NE(surprise((Vector6d() << 0, 0, 0, 0, 0, 8.0).finished(), nullptr).find("turn rate"),
            std::string::npos);
  // Walking at 2 Hz taken for 10 Hz: 0.7 m then 0.3 m steps look like 40 m/s^2.
  const Vector6d slow = (Vector6d() << 3, 0, 0, 0, 0, 0).finished();
  EXPECT_NE(surprise((Vector6d() << 7, 0, 0, 0, 0, 0).finished(), &slow).find("acceleration"),
            std::string::npos);
  EXPECT_NE(surprise((Vector6d() << 10, 0, 0, 0, 0, 2.0).finished(), &cruise)
                .find("angular acceleration"),
            std::string::npos);

  // Degenerate: the registration cannot vouch for the weak direction, the motion model can.
  h = {};
  h.degenerate = true;
  judgeMotion(h, (Vector6d() << 10.5, 0, 0, 0, 0, 0).finished(), &slow, 0.1, cfg);
  EXPECT_NE(h.problem.find("degenerate and acceleration"), std::string::npos) << h.problem;
  h = {};
  h.degenerate = true;
  judgeMotion(h, cruise, &cruise, 0.1, cfg);
  EXPECT_TRUE(h.healthy()) << h.problem;
}

TEST(FramePeriod, MedianOfTheStampsGapsStayGaps) {
  FramePeriod p(0.1);
  EXPECT_DOUBLE_EQ(p.period(), 0.1);  // assumed until the stamps say otherwise
  p.add(0.5);
  EXPECT_DOUBLE_EQ(p.period(), 0.5);  // a 2 Hz recording
  p.add(0.5);
  p.add(3.0);  // five scans dropped
  p.add(0.0);  // a repeated stamp: ignored
  EXPECT_DOUBLE_EQ(p.period(), 0.5);
  EXPECT_DOUBLE_EQ(p.periods(3.0), 6.0);
  EXPECT_DOUBLE_EQ(p.periods(0.2), 1.0);
  FramePeriod gap_first(0.1);
  gap_first.add(0.6);
  gap_first.add(0.1);
  EXPECT_DOUBLE_EQ(gap_first.period(), 0.1);  // of a period and a gap: the period
}

TEST(FileNameStamps, SecondsAndEpochIntegersAreStampsFrameNumbersAreNot) {
  EXPECT_EQ(fileNameStamp("1317354748.213624.pcd"), 1317354748213624);
  EXPECT_EQ(fileNameStamp("1317354748.pcd"), 1317354748000000);
  EXPECT_EQ(fileNameStamp("1317354748213.pcd"), 1317354748213000);        // ms
  EXPECT_EQ(fileNameStamp("1317354748213624.ply"), 1317354748213624);     // us
  EXPECT_EQ(fileNameStamp("1317354748213624512.pcd"), 1317354748213625);  // ns
  EXPECT_FALSE(fileNameStamp("000123.pcd"));
  EXPECT_FALSE(fileNameStamp("scan_1317354748.pcd"));
  EXPECT_FALSE(fileNameStamp("12.5.pcd"));
  EXPECT_FALSE(fileNameStamp("1317354748.2x.pcd"));
  EXPECT_EQ(fileNameStamps({"1317354748.0.pcd", "1317354748.5.pcd"}),
            (std::vector<std::int64_t>{1317354748000000, 1317354748500000}));
  EXPECT_TRUE(fileNameStamps({"1317354748.5.pcd", "1317354748.0.pcd"}).empty());  // not rising
  EXPECT_TRUE(fileNameStamps({"1317354748.0.pcd", "000001.pcd"}).empty());
}

TEST(TrackingMonitor, LostAfterTheConfiguredRunOfUnhealthyFramesAndStaysLost) {
  TrackingMonitor m(3);
  EXPECT_EQ(m.update(true), TrackingState::kTracking);
  EXPECT_EQ(m.update(false), TrackingState::kDegraded);
  EXPECT_EQ(m.update(true), TrackingState::kTracking);  // a run, not a total
  EXPECT_EQ(m.update(false), TrackingState::kDegraded);
  EXPECT_EQ(m.update(false), TrackingState::kDegraded);
  EXPECT_EQ(m.update(false), TrackingState::kLost);
  EXPECT_EQ(m.update(true), TrackingState::kLost);
  EXPECT_EQ(trackingStateName(TrackingState::kLost), "lost");
  EXPECT_EQ(trackingStateName(TrackingState::kDegraded), "degraded");
}

TEST(PointTimes, AzimuthTimesFollowTheSweep) {
  // socc-sim / KITTI convention: starts facing backwards (180 deg), turns clockwise.
  const socc::Points pts = {{-10, 0.01f, 0}, {0, 10, 0}, {10, 0, 0}, {0, -10, 0}, {-10, -0.01f, 0}};
  const std::vector<float> t = azimuthTimes(pts, {0.1, 180.0, true, 0.0});
  EXPECT_NEAR(t[0], 0.0, 1e-4);
  EXPECT_NEAR(t[1], 0.025, 1e-6);
  EXPECT_NEAR(t[2], 0.05, 1e-6);
  EXPECT_NEAR(t[3], 0.075, 1e-6);
  EXPECT_NEAR(t[4], 0.1, 1e-4);
  // Timestamp at the end of the sweep: times are negative, the sweep's middle at -0.05 s.
  const std::vector<float> end = azimuthTimes(pts, {0.1, 180.0, true, 1.0});
  EXPECT_NEAR(end[2], -0.05, 1e-6);
  socc::LabeledCloud c;
  c.points = pts;
  c.times = end;
  EXPECT_NEAR(sweepMidTime(c), -0.05, 1e-4);
}
