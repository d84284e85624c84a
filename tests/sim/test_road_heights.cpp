// The road under a recorded route: its grade follows the attitude, its heights the GPS over long
// distances, its revisits meet; only heights change.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "socc/sim/road_heights.hpp"
#include "socc/sim/road_report.hpp"

namespace socc::sim {
namespace {

// A sensor pose at p heading along the horizontal direction `heading`, nose up by atan(grade).
Eigen::Isometry3d poseAt(const Eigen::Vector3d& p, const Eigen::Vector2d& heading, double grade) {
  const Eigen::Vector3d forward = Eigen::Vector3d(heading.x(), heading.y(), grade).normalized();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = forward;
  pose.linear().col(1) = left;
  pose.linear().col(2) = forward.cross(left);
  pose.translation() = p;
  return pose;
}

// Out 200 m along +x, a U-turn, back 200 m in the other lane (3.5 m to the left), one pose a
// metre, on flat ground recorded with a height drift of `drift` per metre driven and an attitude
// that agrees with it (a pitch bias: nose up both ways), so only the revisit says it is flat.
Poses outAndBack(double drift) {
  std::vector<Eigen::Vector2d> xy;
  for (int x = 0; x <= 200; ++x) xy.emplace_back(x, 0.0);
  for (int a = 1; a < 6; ++a) {
    const double t = M_PI * a / 6.0 - M_PI / 2.0;
    xy.emplace_back(200.0 + 1.75 * std::cos(t), 1.75 + 1.75 * std::sin(t));
  }
  for (int x = 200; x >= 0; --x) xy.emplace_back(x, 3.5);
  Poses poses;
  double s = 0.0;
  for (std::size_t k = 0; k < xy.size(); ++k) {
    if (k > 0) s += (xy[k] - xy[k - 1]).norm();
    const std::size_t next = std::min(k + 1, xy.size() - 1);
    const std::size_t before = next == k ? k - 1 : k;
    const Eigen::Vector2d heading = (xy[next] - xy[before]).normalized();
    poses.push_back(poseAt(Eigen::Vector3d(xy[k].x(), xy[k].y(), drift * s), heading, drift));
  }
  return poses;
}

TEST(RoadHeights, ThePassesOfARevisitedStreetComeToOneHeight) {
  const Poses recorded = outAndBack(0.01);  // 4 m apart where the drive ends
  const RoadHeights levelled = fuseRoadHeights(recorded);
  ASSERT_EQ(levelled.poses.size(), recorded.size());
  EXPECT_GT(levelled.revisit_pairs, 100u);
  EXPECT_GT(levelled.max_change, 1.0);
  EXPECT_LT((levelled.poses[0].translation() - recorded[0].translation()).norm(), 1e-6);
  const std::size_t back = 201 + 5;  // the first pose of the way back
  double worst = 0.0;
  for (std::size_t k = back; k < recorded.size(); ++k) {
    const double x = levelled.poses[k].translation().x();
    if (x > 150.0) continue;  // within 50 m of driving of the outward pass: not a revisit
    const auto out = static_cast<std::size_t>(std::lround(x));
    worst = std::max(worst, std::abs(levelled.poses[k].translation().z() -
                                     levelled.poses[out].translation().z()));
  }
  EXPECT_LT(worst, 0.05) << "recorded: "
                         << recorded.back().translation().z() - recorded[0].translation().z();
}

TEST(RoadHeights, OnlyHeightsChange) {
  const Poses recorded = outAndBack(0.01);
  const RoadHeights levelled = fuseRoadHeights(recorded);
  for (std::size_t k = 0; k < recorded.size(); ++k) {
    EXPECT_TRUE(levelled.poses[k].linear().isApprox(recorded[k].linear(), 0.0)) << k;
    EXPECT_EQ(levelled.poses[k].translation().head<2>(), recorded[k].translation().head<2>());
  }
}

// A straight route along +x, one pose a metre, at `height(x)` with the attitude `grade(x)`.
template <typename Height, typename Grade>
Poses straightRoute(int metres, Height height, Grade grade) {
  Poses route;
  for (int x = 0; x < metres; ++x)
    route.push_back(poseAt(Eigen::Vector3d(x, 0.0, height(x)), Eigen::Vector2d::UnitX(), grade(x)));
  return route;
}

TEST(RoadHeights, HeightsThatAgreeWithTheAttitudeStay) {
  const Poses hill = straightRoute(
      600, [](double x) { return 10.0 * std::sin(x / 100.0); },
      [](double x) { return 0.1 * std::cos(x / 100.0); });
  const RoadHeights road = fuseRoadHeights(hill);
  EXPECT_EQ(road.revisit_pairs, 0u);
  EXPECT_LT(road.max_change, 0.05);  // the bend term rounds its crests (curvature 0.001 / m)
}

TEST(RoadHeights, AGpsLiftUnderTheCarIsNotARamp) {
  // KITTI 08's start: the recorded heights climb 10 m within 30 m, the pitch does not; then
  // 3 km of hills on which both agree (they tell the sensor's pitch from a GPS step).
  const auto hill = [](double x) { return 10.0 * std::sin(x / 150.0); };
  const Poses lift = straightRoute(
      3000, [&](double x) { return hill(x) + std::clamp((x - 50.0) / 3.0, 0.0, 10.0); },
      [](double x) { return std::cos(x / 150.0) / 15.0; });
  const RoadHeights road = fuseRoadHeights(lift);
  double worst = 0.0;  // the road's grade over 10 m against the hill's
  for (std::size_t k = 0; k + 10 < road.poses.size(); ++k) {
    const double x = static_cast<double>(k);
    const double grade =
        (road.poses[k + 10].translation().z() - road.poses[k].translation().z()) / 10.0;
    worst = std::max(worst, std::abs(grade - (hill(x + 10.0) - hill(x)) / 10.0));
  }
  EXPECT_LT(worst, 0.03) << "recorded: 0.33";
  EXPECT_NEAR(road.sensor_pitch, 0.0, 0.002);
}

TEST(RoadHeights, ASensorPitchedAgainstTheRoadIsEstimatedNotIntegrated) {
  // 3 km on level ground, the sensor 0.5 deg nose up: integrated, 26 m of climb.
  const Poses pitched = straightRoute(
      3000, [](double) { return 0.0; }, [](double) { return 0.0087; });
  const RoadHeights road = fuseRoadHeights(pitched);
  EXPECT_LT(road.max_change, 0.1);
  EXPECT_NEAR(road.sensor_pitch, std::atan(0.0087), 0.0005);
}

TEST(RoadHeights, AStreetCrossedAgainComesToOneHeightToo) {
  Poses route;  // east along y = 0; then, after a drive round, north across it recorded 6 m higher
  for (int x = -100; x <= 100; ++x)
    route.push_back(poseAt(Eigen::Vector3d(x, 0.0, 0.0), Eigen::Vector2d::UnitX(), 0.0));
  for (int y = -100; y <= 100; ++y)
    route.push_back(poseAt(Eigen::Vector3d(0.0, y, 6.0), Eigen::Vector2d::UnitY(), 0.0));
  const RoadHeights levelled = fuseRoadHeights(route);
  EXPECT_GT(levelled.revisit_pairs, 0u);
  EXPECT_NEAR(levelled.poses[201 + 100].translation().z(), levelled.poses[100].translation().z(),
              0.1);
}

TEST(RoadHeights, StandingStillAtTheStartAndAtTheTurnIsFine) {
  Poses route = outAndBack(0.01);
  route.insert(route.begin(), 10, route.front());     // waits before driving off
  route.insert(route.begin() + 215, 20, route[215]);  // and at the turn
  const RoadHeights levelled = fuseRoadHeights(route);
  EXPECT_GT(levelled.revisit_pairs, 100u);
  for (const Eigen::Isometry3d& pose : levelled.poses) ASSERT_TRUE(pose.matrix().allFinite());
  EXPECT_TRUE(levelled.poses[0].isApprox(levelled.poses[9], 1e-12));
}

TEST(RoadHeights, ARevisitIsTiedWithoutTheSensorsPitch) {
  // Up a hill street to its crest and down it again in the same lane, the heights exact, the
  // sensor 1 deg nose up against the road; the way up recorded every 6 m, so a pose of the way
  // down lies up to 3 m along the street from the nearest pose up. The pitch must not enter its
  // tie (0.0175 * 3 m = 5 cm a tie).
  const double pitch = std::tan(M_PI / 180.0);
  const auto height = [](double x) { return 8.0 * std::sin(M_PI * x / 600.0); };
  const auto grade = [](double x) { return 8.0 * M_PI / 600.0 * std::cos(M_PI * x / 600.0); };
  Poses route;
  for (int x = 0; x <= 300; x += 6)
    route.push_back(
        poseAt(Eigen::Vector3d(x, 0.0, height(x)), Eigen::Vector2d::UnitX(), grade(x) + pitch));
  for (int x = 299; x >= 0; --x)
    route.push_back(
        poseAt(Eigen::Vector3d(x, 0.0, height(x)), -Eigen::Vector2d::UnitX(), -grade(x) + pitch));
  const RoadHeights road = fuseRoadHeights(route);
  EXPECT_GT(road.revisit_pairs, 200u);
  EXPECT_LT(road.max_change, 0.02);  // tied with the attitude's grade: 0.37 m
  EXPECT_NEAR(road.sensor_pitch, M_PI / 180.0, 0.001);
}

TEST(RoadReport, MeasuresTheRecordedHeightsAndTheRoadAgainstTheAttitude) {
  const Poses recorded = outAndBack(0.01);  // a height drift the attitude shares: no grade error
  const RoadReport report = roadReport(recorded);
  EXPECT_LT(report.recorded.grade_rms, 0.001);
  EXPECT_NEAR(report.recorded.steepest, 0.01, 1e-3);
  EXPECT_EQ(report.recorded.worst_revisit, 0.0);         // the lanes are 3.5 m apart: not one place
  EXPECT_GT(roadFit(recorded, 4.0).worst_revisit, 3.0);  // 4 m apart where the drive ends
  EXPECT_LT(roadFit(report.heights.poses, 4.0).worst_revisit, 0.05);
  EXPECT_EQ(report.heights.poses.size(), recorded.size());
}

TEST(RoadReport, AGpsLiftIsAGradeErrorAndASteepStretch) {
  const Poses lift = straightRoute(
      1000, [](double x) { return std::clamp((x - 50.0) / 3.0, 0.0, 10.0); },
      [](double) { return 0.0; });
  const RoadReport report = roadReport(lift);
  EXPECT_NEAR(report.recorded.steepest, 1.0 / 3.0, 0.01);
  EXPECT_GT(report.recorded.grade_rms, 0.05);
  EXPECT_LT(report.road.steepest, 0.02);
  EXPECT_LT(report.road.grade_rms, 0.01);
  EXPECT_EQ(report.recorded.worst_revisit, 0.0);
}

}  // namespace
}  // namespace socc::sim
