// Per-laser range calibration (range_calibration.hpp): lasers whose ranges carry different
// scales disagree about one wall, and the fit finds each laser's scale relative to the others by
// comparing them on each piece of wall, whatever the map's points say (a common scale of all
// lasers is not observable and is left alone).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "socc/odom/range_calibration.hpp"
#include "socc/odom/scan_map.hpp"
#include "walled_ground.hpp"

using namespace socc::odom;

namespace {

constexpr int kLasers = 16;
constexpr double kDegree = M_PI / 180.0;

// -2.95 .. +3.05 deg, 0.4 deg apart: each in the middle of one of the calibration's 0.1 deg bins.
double elevationOf(int laser) {
  return (-2.95 + 0.4 * laser) * kDegree;
}

// Scales of -0.4..+0.4 % and offsets of -3..+3 cm, mixed over the lasers.
std::vector<double> errorScales() {
  std::vector<double> scale;
  for (int k = 0; k < kLasers; ++k) scale.push_back(0.004 * std::sin(1.7 * k + 0.3));
  return scale;
}
std::vector<double> errorOffsets() {
  std::vector<double> offset;
  for (int k = 0; k < kLasers; ++k) offset.push_back(0.03 * std::cos(2.3 * k));
  return offset;
}

// A walled yard: flat ground 1.73 m below the sensor, walls at x = -40 / +50 and y = -30 / +25 m.
constexpr socc::odom_test::WalledGround kYard{-1.73, -40.0, 50.0, -30.0, 25.0};

// The scan at origin (sensor frame, axes of the map) of a sensor whose laser k reads its ranges
// as r * (1 + scale[k]) + offset[k].
socc::LabeledCloud yardScan(const Eigen::Vector3d& origin, const std::vector<double>& scale,
                            const std::vector<double>& offset) {
  socc::LabeledCloud scan;
  for (int k = 0; k < kLasers; ++k)
    for (int c = 0; c < 1800; ++c) {
      const double azimuth = 2.0 * M_PI * c / 1800.0;
      const double e = elevationOf(k);
      const Eigen::Vector3d d(std::cos(e) * std::cos(azimuth), std::cos(e) * std::sin(azimuth),
                              std::sin(e));
      const double r = socc::odom_test::rangeTo(kYard, origin, d);
      if (r < 0.0 || r > 100.0) continue;
      const double reported =
          r * (1.0 + scale[static_cast<std::size_t>(k)]) + offset[static_cast<std::size_t>(k)];
      scan.points.push_back((reported * d).cast<float>());
    }
  return scan;
}

// The yard's map as scans of a sensor with these errors give it from a few places.
LocalMap yardMap(const std::vector<double>& scale, const std::vector<double>& offset) {
  socc::LabeledCloud all;
  for (const Eigen::Vector3d& origin :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(8, -5, 0), Eigen::Vector3d(-10, 6, 0)})
    for (const Eigen::Vector3f& p : yardScan(origin, scale, offset).points)
      all.points.push_back(p + origin.cast<float>());
  return buildScanMap(all, 0.5);
}

// The calibration after observing the sensor's scans from a few places at their true poses, on
// the exact map or on the map that the sensor made itself.
RangeCalibration observed(const std::vector<double>& scale, const std::vector<double>& offset,
                          bool own_map = false) {
  const std::vector<double> zero(kLasers, 0.0);
  const LocalMap map = own_map ? yardMap(scale, offset) : yardMap(zero, zero);
  RangeCalibrationParams params;
  params.samples = 100000;  // every point: the test's scans are small
  params.fit_every = 1;
  RangeCalibration calibration(params);
  for (int round = 0; round < 3; ++round)
    for (const Eigen::Vector3d& origin :
         {Eigen::Vector3d(2, 1, 0), Eigen::Vector3d(-5, -3, 0), Eigen::Vector3d(6, 4, 0)}) {
      socc::LabeledCloud scan = yardScan(origin, scale, offset);
      calibration.apply(scan);
      calibration.observe(scan.points, scan.points, Eigen::Isometry3d(Eigen::Translation3d(origin)),
                          map);
    }
  return calibration;
}

// Each wall point of the sensor's scan at origin, corrected by calibration, is at its exact range
// times (1 + a common scale) plus a common offset, to tolerance x range + 3 mm: the lasers agree.
// Returns the common scale and offset (a least-squares line through the corrected against the
// exact ranges).
Eigen::Vector2d expectAgreeing(const RangeCalibration& calibration,
                               const std::vector<double>& scale, const std::vector<double>& offset,
                               double tolerance = 2e-4) {
  const Eigen::Vector3d origin(1, 2, 0);
  socc::LabeledCloud scan = yardScan(origin, scale, offset);
  const std::vector<double> zero(kLasers, 0.0);
  const socc::LabeledCloud exact = yardScan(origin, zero, zero);  // the same rays
  calibration.apply(scan);
  EXPECT_EQ(scan.size(), exact.size());
  std::vector<std::pair<double, double>> walls;  // exact, corrected range
  for (std::size_t i = 0; i < std::min(scan.size(), exact.size()); ++i) {
    if (exact.points[i].z() < -1.7f) continue;  // the ground: no wall, not calibrated on
    EXPECT_NEAR(scan.points[i].normalized().dot(exact.points[i].normalized()), 1.0, 1e-6);
    walls.emplace_back(exact.points[i].cast<double>().norm(), scan.points[i].cast<double>().norm());
  }
  EXPECT_GT(walls.size(), 1000u);
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const auto& [r, corrected] : walls) {
    const Eigen::Vector2d g(r, 1.0);
    normal += g * g.transpose();
    rhs += g * (corrected - r);
  }
  const Eigen::Vector2d common = normal.ldlt().solve(rhs);  // scale, offset
  double worst = 0.0, worst_range = 0.0;  // the largest excess over the tolerance, and where
  for (const auto& [r, corrected] : walls) {
    const double excess =
        std::abs(corrected - (r * (1.0 + common(0)) + common(1))) - (tolerance * r + 0.003);
    if (excess > worst) {
      worst = excess;
      worst_range = r;
    }
  }
  EXPECT_EQ(worst, 0.0) << "a wall point at " << worst_range << " m is " << worst
                        << " m further off than the tolerance";
  return common;
}

}  // namespace

TEST(RangeCalibration, ItsCorrectionLeavesTheLasersAgreeing) {
  const std::vector<double> scale = errorScales(), offset = errorOffsets();
  const RangeCalibration calibration = observed(scale, offset);
  EXPECT_EQ(calibration.lasers().size(), static_cast<std::size_t>(kLasers));
  expectAgreeing(calibration, scale, offset);
}

TEST(RangeCalibration, TheLasersAreTheReferenceNotTheMap) {
  // The map's walls are made of the same lasers' points, each with its own error: a laser
  // compared with them would keep part of its error.
  const std::vector<double> scale = errorScales(), offset = errorOffsets();
  // The lowest laser sees walls only in a narrow band of ranges before the ground, whose map
  // voxels hold other lasers' points: its offset and scale come out 1 cm off at 33 m (0.03 %).
  // A fit against the map's points keeps part of each laser's error and fails this test.
  const RangeCalibration calibration = observed(scale, offset, true);
  EXPECT_EQ(calibration.lasers().size(), static_cast<std::size_t>(kLasers));
  expectAgreeing(calibration, scale, offset, 3e-4);
}

TEST(RangeCalibration, LeavesACommonScaleAlone) {
  // Every laser 0.3 % long: the world looks 0.3 % larger, which no map can tell.
  const std::vector<double> scale(kLasers, 0.003), offset(kLasers, 0.0);
  const Eigen::Vector2d common = expectAgreeing(observed(scale, offset), scale, offset);
  EXPECT_NEAR(common(0), 0.003, 2e-5);
  EXPECT_NEAR(common(1), 0.0, 2e-3);
}

TEST(RangeCalibration, MovesNoPointBeforeItsFirstFit) {
  // The lasers seen are listed from their first observation, with no correction until the joint
  // problem is solved (every fit_every frames).
  const std::vector<double> scale = errorScales(), offset = errorOffsets();
  const std::vector<double> zero(kLasers, 0.0);
  RangeCalibrationParams params;
  params.samples = 100000;
  params.fit_every = 3;
  RangeCalibration calibration(params);
  const LocalMap map = yardMap(zero, zero);
  const Eigen::Vector3d origin(2, 1, 0);
  const Eigen::Isometry3d pose(Eigen::Translation3d{origin});
  const socc::LabeledCloud scan = yardScan(origin, scale, offset);
  for (int frame = 0; frame < 2; ++frame) calibration.observe(scan.points, scan.points, pose, map);
  EXPECT_FALSE(calibration.corrects());
  ASSERT_EQ(calibration.lasers().size(), static_cast<std::size_t>(kLasers));
  for (const RangeCalibration::Laser& laser : calibration.lasers()) {
    EXPECT_EQ(laser.offset, 0.0);
    EXPECT_EQ(laser.scale, 0.0);
  }
  socc::LabeledCloud applied = scan;
  calibration.apply(applied);
  EXPECT_EQ(applied.points, scan.points);

  calibration.observe(scan.points, scan.points, pose, map);
  EXPECT_TRUE(calibration.corrects());
  calibration.apply(applied);
  EXPECT_NE(applied.points, scan.points);
}

TEST(RangeCalibration, ALaserNoLongerSeenKeepsItsFactoryCalibration) {
  // A laser takes the shift that holds the well-seen lasers' mean only in what its own evidence
  // determines, and its own estimate fades with its evidence: once that has faded (the lowest
  // laser is cut from the scans after the first three, and the evidence fades within a frame
  // here), it goes back to no correction (docs/robustness.md "Corrected where the evidence is").
  const std::vector<double> scale = errorScales(), offset = errorOffsets();
  const std::vector<double> zero(kLasers, 0.0);
  const LocalMap map = yardMap(zero, zero);
  RangeCalibrationParams params;
  params.samples = 100000;
  params.fit_every = 1;
  params.memory_frames = 0.5;
  RangeCalibration calibration(params);
  const Eigen::Vector3d origins[3] = {{2, 1, 0}, {-5, -3, 0}, {6, 4, 0}};
  for (int frame = 0; frame < 9; ++frame) {
    const Eigen::Vector3d& origin = origins[frame % 3];
    socc::LabeledCloud scan = yardScan(origin, scale, offset);
    if (frame >= 3) {
      socc::LabeledCloud without;
      for (const Eigen::Vector3f& p : scan.points)
        if (std::abs(std::atan2(p.z(), p.head<2>().norm()) - elevationOf(0)) > 1e-4)
          without.points.push_back(p);
      scan = without;
    }
    calibration.apply(scan);
    calibration.observe(scan.points, scan.points, Eigen::Isometry3d(Eigen::Translation3d(origin)),
                        map);
  }
  const std::vector<RangeCalibration::Laser> lasers = calibration.lasers();
  ASSERT_EQ(lasers.size(), static_cast<std::size_t>(kLasers));
  for (const double range : {10.0, 30.0, 50.0})
    EXPECT_NEAR(lasers.front().offset + lasers.front().scale * range, 0.0, 0.001) << range << " m";
  // The others are still corrected: each laser above the lowest four (which see walls in a
  // narrower band of ranges before the ground) to its error less a common part, within 3 mm +
  // 0.02 % of range at the walls' ranges.
  Eigen::Vector2d common = Eigen::Vector2d::Zero();
  for (std::size_t k = 4; k < lasers.size(); ++k)
    common += Eigen::Vector2d(lasers[k].offset - offset[k], lasers[k].scale - scale[k]);
  common /= static_cast<double>(lasers.size() - 4);
  for (std::size_t k = 4; k < lasers.size(); ++k)
    for (const double range : {20.0, 40.0})
      EXPECT_NEAR(lasers[k].offset - offset[k] + (lasers[k].scale - scale[k]) * range,
                  common(0) + common(1) * range, 0.003 + 2e-4 * range)
          << "laser " << k << " at " << range << " m";
}
