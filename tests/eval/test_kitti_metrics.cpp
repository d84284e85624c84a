// Hand-computed KITTI metric cases on a straight 1 m-per-frame ground truth.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/eval/kitti_metrics.hpp"

namespace socc::eval {
namespace {

Poses straightLine(std::size_t n, double step) {
  Poses poses;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation().x() = step * static_cast<double>(i);
    poses.push_back(p);
  }
  return poses;
}

TEST(KittiMetrics, TrajectoryDistances) {
  const std::vector<double> d = trajectoryDistances(straightLine(4, 2.0));
  EXPECT_EQ(d, (std::vector<double>{0, 2, 4, 6}));
}

TEST(KittiMetrics, PerfectEstimateHasZeroError) {
  const Poses gt = straightLine(301, 1.0);
  const KittiMetrics m = computeKittiMetrics(gt, gt, {100, 200});
  ASSERT_TRUE(m.valid());
  EXPECT_NEAR(m.t_err_percent, 0.0, 1e-12);
  EXPECT_NEAR(m.r_err_deg_per_100m, 0.0, 1e-9);
}

TEST(KittiMetrics, ScaleDriftGivesKnownTranslationError) {
  // The last frame of a 100 m segment is the first one *beyond* 100 m: 101 frames later, so the
  // ground-truth delta is 101 m and the estimate's is 1.01 * 101 m -> t_err = 1.01 * 101 / 100 %.
  const Poses gt = straightLine(1001, 1.0);
  const Poses est = straightLine(1001, 1.01);
  const KittiMetrics m = computeKittiMetrics(gt, est, {100});
  // first frames 0, 10, ..., 890 have a frame 101 steps later (the last is frame 1000).
  EXPECT_EQ(m.segments.size(), 90u);
  EXPECT_NEAR(m.t_err_percent, 1.0 * 101.0 / 100.0, 1e-9);
  EXPECT_NEAR(m.r_err_deg_per_100m, 0.0, 1e-9);
  ASSERT_EQ(m.per_length.size(), 1u);
  EXPECT_EQ(m.per_length[0].segments, 90u);
}

TEST(KittiMetrics, ErrorsBySpeedBinTheSegmentsByDevkitSpeed) {
  // 1 m per frame: a 10 m segment spans 12 frames (devkit: first frame past the length), so
  // its speed is 10 / 1.2 = 8.33 m/s, inside the +-2 m/s windows of the 8 and 10 m/s bins.
  const Poses gt = straightLine(101, 1.0);
  const KittiMetrics m = computeKittiMetrics(gt, straightLine(101, 1.01), {10.0}, 1);
  const std::vector<KittiSpeedError> bins = kittiErrorsBySpeed(m);
  ASSERT_EQ(bins.size(), 2u);
  EXPECT_EQ(bins[0].speed, 8.0);
  EXPECT_EQ(bins[1].speed, 10.0);
  for (const auto& b : bins) {
    EXPECT_EQ(b.segments, m.segments.size());
    EXPECT_NEAR(b.t_err_percent, m.t_err_percent, 1e-9);
  }
  EXPECT_EQ(kittiErrorsBySpeed(m, 0.05).front().speed, 16.0);  // 20 Hz: twice the speed
  EXPECT_THROW(kittiErrorsBySpeed(m, 0.0), std::invalid_argument);
}

TEST(KittiMetrics, YawDriftGivesKnownRotationError) {
  // Each estimated pose is yawed by theta more than the previous one: a 101-frame segment has a
  // rotation error of 101 theta over 100 m.
  const double theta = 0.001;  // rad per frame
  const Poses gt = straightLine(501, 1.0);
  Poses est = gt;
  for (std::size_t i = 0; i < est.size(); ++i)
    est[i].linear() =
        Eigen::AngleAxisd(theta * static_cast<double>(i), Eigen::Vector3d::UnitZ()).matrix();
  const KittiMetrics m = computeKittiMetrics(gt, est, {100});
  ASSERT_TRUE(m.valid());
  EXPECT_NEAR(m.r_err_deg_per_100m, 101.0 * theta * 180.0 / M_PI, 1e-9);
}

TEST(KittiMetrics, StepAndLengthsChangeSegmentCount) {
  const Poses gt = straightLine(301, 1.0);
  EXPECT_EQ(computeKittiMetrics(gt, gt, {100}, 1).segments.size(), 200u);  // 0..199
  EXPECT_EQ(computeKittiMetrics(gt, gt, {100, 200}, 10).segments.size(), 20u + 10u);
}

TEST(KittiMetrics, TooShortIsInvalidNotACrash) {
  const Poses gt = straightLine(50, 1.0);
  const KittiMetrics m = computeKittiMetrics(gt, gt);
  EXPECT_FALSE(m.valid());
  EXPECT_EQ(m.per_length.size(), 8u);
}

TEST(KittiMetrics, BadInputThrows) {
  const Poses gt = straightLine(50, 1.0);
  EXPECT_THROW(computeKittiMetrics(gt, straightLine(49, 1.0)), std::invalid_argument);
  EXPECT_THROW(computeKittiMetrics(gt, gt, {0.0}), std::invalid_argument);
  EXPECT_THROW(computeKittiMetrics(gt, gt, {10.0}, 0), std::invalid_argument);
}

TEST(KittiMetrics, RotationAngle) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  EXPECT_NEAR(rotationAngle(p), 0.3, 1e-12);
}

}  // namespace
}  // namespace socc::eval
