// The realism error models: "none" is the exact scan, each model does what sim/README.md says
// at the stated magnitude, and everything stays a function of the seed.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/sim/beam_calibration.hpp"
#include "socc/sim/body_motion.hpp"
#include "socc/sim/label_noise.hpp"
#include "socc/sim/room_model.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/semantic_ids.hpp"
#include "socc/sim/surface_model.hpp"
#include "socc/sim/trajectory.hpp"

namespace socc::sim {
namespace {

Scene wallScene(std::uint16_t label) {
  Poses still(2, Eigen::Isometry3d::Identity());
  const Box wall = makeBox({15, 0, 0}, {1, 40, 20});
  return Scene{World({{wall, label}}, {}, nullptr, {}, 1.73), Trajectory(still, 0.1), true};
}

// Mean and RMS of the points' x minus the wall face at x = 14.5.
std::pair<double, double> wallError(const SimulatedScan& s) {
  double sum = 0.0;
  double sq = 0.0;
  for (const auto& p : s.points) {
    sum += p.x() - 14.5;
    sq += (p.x() - 14.5) * (p.x() - 14.5);
  }
  const auto n = static_cast<double>(std::max<std::size_t>(1, s.points.size()));
  return {sum / n, std::sqrt(sq / n)};
}

TEST(Realism, NonePresetIsTheExactScan) {
  const Realism none = realismPreset("none");
  EXPECT_FALSE(none.anyScanError());
  const Scene scene = wallScene(raw::kBuilding);
  const SimulatedScan a = simulateScan(scene, lidarPreset("vlp16"), 0.0, 2, {true, 4});
  const SimulatedScan b = simulateScan(scene, lidarPreset("vlp16"), 0.0, 2, {true, 4, &none});
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_TRUE(b.exact_labels.empty());
  EXPECT_THROW(realismPreset("mars"), std::invalid_argument);
}

TEST(Realism, EveryGroupSwitchesOff) {
  Realism r = realismPreset("kitti");
  EXPECT_TRUE(r.anyScanError());
  disableRealism(r, {"beams", "returns", "terrain", "motion", "labels"});
  EXPECT_FALSE(r.anyScanError());
  EXPECT_EQ(r.motion.bump_pitch_deg, 0.0);
  EXPECT_THROW(disableRealism(r, {"weather"}), std::invalid_argument);
}

TEST(Realism, SingleModelsSwitchOffForAblations) {
  Realism r = realismPreset("kitti");
  disableRealism(r, {"range_walk", "body", "elevation_bias"});
  EXPECT_EQ(r.returns.range_walk, 0.0);
  EXPECT_GT(r.returns.glass_fraction, 0.0);
  EXPECT_EQ(r.motion.bump_pitch_deg, 0.0);
  EXPECT_GT(r.motion.vibration_deg, 0.0);
  EXPECT_EQ(r.beams.elevation_bias_deg, 0.0);
  EXPECT_GT(r.beams.elevation_sigma_deg, 0.0);
  disableRealism(r, {"beam_azimuths"});
  EXPECT_EQ(r.beams.azimuth_sigma_deg, 0.0);
  EXPECT_GT(r.beams.elevation_sigma_deg, 0.0);
  disableRealism(r, {"beam_elevations"});
  EXPECT_EQ(r.beams.elevation_sigma_deg, 0.0);
  EXPECT_GT(r.beams.range_offset_sigma, 0.0);
}

TEST(Realism, BeamCalibrationIsFixedPerSensorAtTheStatedSpread) {
  const BeamErrors e = realismPreset("kitti").beams;
  const BeamCalibration a = drawBeamCalibration(e, 64, 7);
  const BeamCalibration b = drawBeamCalibration(e, 64, 7);
  const BeamCalibration c = drawBeamCalibration(e, 64, 8);
  EXPECT_EQ(a.elevation_error, b.elevation_error);
  EXPECT_NE(a.elevation_error, c.elevation_error);
  double mean = 0.0;
  double sq = 0.0;
  for (const double v : a.elevation_error) mean += v / 64.0;
  for (const double v : a.elevation_error) sq += (v - mean) * (v - mean) / 64.0;
  const double deg = M_PI / 180.0;
  EXPECT_NEAR(mean, e.elevation_bias_deg * deg, 4 * e.elevation_sigma_deg * deg / 8.0);
  EXPECT_NEAR(std::sqrt(sq), e.elevation_sigma_deg * deg, 0.4 * e.elevation_sigma_deg * deg);
}

// One sensor instance can drive through many worlds: its calibration follows sensor_seed.
TEST(Realism, TheSensorInstanceHasItsOwnSeed) {
  Realism beams_only = realismPreset("none");
  beams_only.beams = realismPreset("kitti").beams;
  const Scene scene = wallScene(raw::kBuilding);
  const LidarModel m = lidarPreset("vlp16");
  const auto scan = [&](std::uint64_t seed, std::optional<std::uint64_t> sensor) {
    return simulateScan(scene, m, 0.0, 1, {false, seed, &beams_only, sensor}).points;
  };
  EXPECT_EQ(scan(3, std::nullopt), scan(3, 3)) << "unset: the sensor of --seed";
  EXPECT_NE(scan(3, 3), scan(3, 4));
  EXPECT_EQ(scan(3, 4), scan(5, 4)) << "beam errors only: the same sensor, the same scan";
}

TEST(Realism, ReturnsAreNoisierAndBiasedButStayOnTheWall) {
  Realism r = realismPreset("kitti");
  disableRealism(r, {"beams", "labels"});
  const Scene scene = wallScene(raw::kBuilding);
  LidarModel m = lidarPreset("vlp16");
  m.range_noise = 0.0;
  const SimulatedScan exact = simulateScan(scene, m, 0.0, 0, {});
  const SimulatedScan real = simulateScan(scene, m, 0.0, 0, {false, 3, &r});
  EXPECT_NEAR(wallError(exact).second, 0.0, 1e-4);
  // Windows drop or push returns behind the facade; the rest stays within centimetres.
  std::size_t behind = 0;
  for (const auto& p : real.points) behind += p.x() > 14.8f ? 1 : 0;
  EXPECT_GT(behind, real.points.size() / 20);
  EXPECT_LT(real.points.size(), exact.points.size());
  EXPECT_EQ(real.exact_labels.size(), real.points.size());
}

TEST(Realism, WindowsShowTheSameStaticRoomsInEveryScan) {
  Realism r = realismPreset("none");
  r.returns.glass_fraction = 1.0;  // the whole facade is glass
  // A building 10 m deep with its facade at x = 14.5, from y = -20 to 20 and z = -10 to 10.
  Poses still(2, Eigen::Isometry3d::Identity());
  const Box building = makeBox({19.5, 0, 0}, {10, 40, 20});
  const World world({{building, raw::kBuilding}}, {}, nullptr, {}, 1.73);
  LidarModel m = lidarPreset("vlp16");
  m.range_noise = 0.0;
  const RoomLayout rooms;
  const auto onGrid = [](double u, double cell) {
    return std::abs(u / cell - std::round(u / cell)) * cell < 0.01;
  };
  // Seen from two places, every return lies on a wall, floor or ceiling of the world-fixed rooms:
  // the back wall 3 m behind the facade, side walls every 4 m from the building's end, floors
  // every 3 m from its base.
  for (const double y : {0.0, 4.0}) {
    Poses at(still);
    for (auto& pose : at) pose.translation().y() = y;
    const SimulatedScan s =
        simulateScan({world, Trajectory(at, 0.1), true}, m, 0.0, 1, {false, 3, &r});
    EXPECT_GT(s.points.size(), 2000u);
    std::size_t side = 0;
    for (const auto& p : s.points) {
      const bool back = std::abs(p.x() - (14.5 + rooms.depth)) < 0.01;
      const bool wall = onGrid(p.y() + 20.0, rooms.width);
      side += wall && !back ? 1 : 0;
      EXPECT_TRUE(back || wall || onGrid(p.z() + 10.0, rooms.storey)) << p.transpose();
      EXPECT_GT(p.x(), 14.5);
      EXPECT_LT(p.x(), 14.5 + rooms.depth + 0.01);
    }
    EXPECT_GT(side, s.points.size() / 10);  // oblique rays end on the rooms' side walls
  }
}

TEST(Realism, InteriorWallsHaveNoWindows) {
  // Indoors (office, corridor) a room behind a wall would stand in the sensor's own free space:
  // the same all-glass wall, as an interior one, returns from its face.
  Realism r = realismPreset("none");
  r.returns.glass_fraction = 1.0;
  Scene scene = wallScene(raw::kBuilding);
  scene.exterior_walls = false;
  LidarModel m = lidarPreset("vlp16");
  m.range_noise = 0.0;
  const SimulatedScan s = simulateScan(scene, m, 0.0, 1, {false, 3, &r});
  EXPECT_GT(s.points.size(), 2000u);
  for (const auto& p : s.points) EXPECT_NEAR(p.x(), 14.5, 0.01);
}

TEST(Realism, RoomsEndAtTheNearestWallAndGlassReflectsGrazingRays) {
  const RoomLayout rooms;
  const Box building = makeBox({10, 0, 0}, {10, 40, 20});  // facade at x = 5, y from -20
  // Straight in through the middle of a room: its back wall.
  const Ray straight{{0, -18, 0.5}, {1, 0, 0}};
  EXPECT_NEAR(*roomTravel(straight, 5.0, building, rooms), rooms.depth, 1e-9);
  // 60 deg off the facade's normal, 1 m before the room's side wall at y = -16: the side wall
  // after 1 / sin(60 deg), not the back wall after 3 / cos(60 deg).
  const Eigen::Vector3d oblique(std::cos(M_PI / 3), std::sin(M_PI / 3), 0.0);
  const Ray steep{Eigen::Vector3d(5, -17, 0.5) - 2.0 * oblique, oblique};
  EXPECT_NEAR(*roomTravel(steep, 2.0, building, rooms), 1.0 / std::sin(M_PI / 3), 1e-9);
  // Beyond the grazing cosine glass reflects the pulse away.
  const Eigen::Vector3d grazing(0.2, std::sqrt(1 - 0.04), 0.0);
  const Ray glancing{Eigen::Vector3d(5, -10, 0.5) - 2.0 * grazing, grazing};
  EXPECT_FALSE(roomTravel(glancing, 2.0, building, rooms).has_value());
  // The roof has no windows.
  const Ray down{{10, 0, 20}, {0, 0, -1}};
  EXPECT_FALSE(roomTravel(down, 10.0, building, rooms).has_value());
}

TEST(Realism, DarkFarSurfacesDropOut) {
  Realism r = realismPreset("none");
  r.returns.detection_threshold = realismPreset("kitti").returns.detection_threshold;
  const Scene near = wallScene(raw::kRoad);  // albedo 0.15 at 15 m: well above the threshold
  const SimulatedScan a = simulateScan(near, lidarPreset("vlp16"), 0.0, 0, {false, 1, &r});
  const SimulatedScan exact = simulateScan(near, lidarPreset("vlp16"), 0.0, 0, {});
  EXPECT_GT(a.points.size(), exact.points.size() * 9 / 10);
  Poses far(2, Eigen::Isometry3d::Identity());
  const Box distant = makeBox({80, 0, 0}, {1, 200, 100});
  const Scene dark{World({{distant, raw::kRoad}}, {}, nullptr, {}, 1.73), Trajectory(far, 0.1)};
  const SimulatedScan b = simulateScan(dark, lidarPreset("vlp16"), 0.0, 0, {false, 1, &r});
  const SimulatedScan b_exact = simulateScan(dark, lidarPreset("vlp16"), 0.0, 0, {});
  EXPECT_LT(b.points.size(), b_exact.points.size() / 5);  // 0.15 / 80^2 < threshold
}

TEST(Realism, GroundUnevennessIsBoundedAndOnlyOnTheGround) {
  const Realism r = realismPreset("kitti");
  const SurfaceModel s(r.returns, r.terrain, 5);
  double peak = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(0.37 * i, 0.11 * i, 0.0);
    peak = std::max(peak, std::abs(s.groundHeight(raw::kRoad, p)));
    EXPECT_EQ(s.groundHeight(raw::kBuilding, p), 0.0);
  }
  EXPECT_GT(peak, 0.3 * r.terrain.road_roughness);
  EXPECT_LE(peak, r.terrain.road_roughness + 1e-12);
}

TEST(Realism, BodyPitchesForwardWhenBrakingAndRollsOutOfTurns) {
  MotionErrors e;
  e.pitch_per_acceleration_deg = 0.2;
  e.roll_per_lateral_deg = 0.4;
  const BodyMotion body(e, 1);
  const Eigen::Isometry3d brake = body.offset(1.0, {-5.0, 0.0, 0.0}, 10.0);
  EXPECT_LT((brake.linear() * Eigen::Vector3d::UnitX()).z(), -0.01);  // nose down
  const Eigen::Isometry3d left = body.offset(1.0, {0.0, 3.0, 0.0}, 10.0);
  EXPECT_GT((left.linear() * Eigen::Vector3d::UnitY()).z(), 0.01);  // left side up
  const Eigen::Isometry3d still = BodyMotion(MotionErrors{}, 1).offset(1.0, {-5, 3, 0}, 10.0);
  EXPECT_TRUE(still.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(Realism, ARouteUnderWayDoesNotPitchAtItsStart) {
  // 10 m/s along x from t = 0: before its first keyframe the route goes on at that speed, so the
  // body sees no acceleration at the start (held there, it pitched the sensor by degrees).
  Poses keyframes;
  for (int k = 0; k < 50; ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = 1.0 * k;
    keyframes.push_back(pose);
  }
  Trajectory route(keyframes, 0.1);
  MotionErrors e;
  e.pitch_per_acceleration_deg = 0.2;
  route.setBodyMotion(BodyMotion(e, 1));
  for (const double t : {0.0, 0.1, 0.2, 2.0}) {
    const Eigen::Isometry3d pose = route.poseAt(t);
    EXPECT_NEAR((pose.linear() * Eigen::Vector3d::UnitX()).z(), 0.0, 1e-9) << "t " << t;
    EXPECT_NEAR(pose.translation().x(), 10.0 * t, 1e-9);
  }
}

TEST(Realism, NetworkLabelsHaveNoMoversAndAStatedScore) {
  EXPECT_EQ(singleScanRawId(raw::kMovingCar), raw::kCar);
  EXPECT_EQ(singleScanRawId(raw::kRoad), raw::kRoad);
  LabelScore perfect;
  perfect.add({40, 40, 10}, {40, 40, 10});
  EXPECT_DOUBLE_EQ(perfect.meanIou(), 1.0);
  LabelScore half;  // road: 1 of 2 right, sidewalk predicted once wrongly -> IoU 1/2 and 0
  half.add({40, 40}, {40, 48});
  EXPECT_EQ(half.classesPresent(), 1);
  EXPECT_DOUBLE_EQ(half.meanIou(), 0.5);
  for (std::uint8_t c = 1; c < kNumClasses; ++c) EXPECT_LT(confusedClass(c, false), kNumClasses);
}

}  // namespace
}  // namespace socc::sim
