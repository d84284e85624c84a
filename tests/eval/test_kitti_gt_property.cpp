// Property test on a real KITTI ground truth: perturbing every step by a known error must give
// that error back as the KITTI metric.
#include <gtest/gtest.h>

#include <filesystem>

#include "socc/eval/kitti_metrics.hpp"
#include "socc/eval/trajectory.hpp"

namespace socc::eval {
namespace {

namespace fs = std::filesystem;

const fs::path kGtDir = fs::path(SOCC_SHARED_DATA_DIR) / "kitti_gt";

Poses loadGt00() {
  return loadTrajectory(kGtDir / "poses" / "00.txt", TrajectoryFormat::kKitti,
                        kGtDir / "calib_00-02.txt")
      .poses;
}

// Re-chains the ground-truth increments after applying `perturb` to each one.
template <typename Perturb>
Poses perturbIncrements(const Poses& gt, Perturb perturb) {
  Poses est = {gt.front()};
  for (std::size_t i = 1; i < gt.size(); ++i)
    est.push_back(est.back() * perturb(gt[i - 1].inverse() * gt[i]));
  return est;
}

class KittiGtProperty : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kGtDir / "poses" / "00.txt"))
      GTEST_SKIP() << "KITTI ground truth not found in " << kGtDir << " (shared data absent)";
  }
};

TEST_F(KittiGtProperty, ScaleErrorOfOnePercent) {
  const Poses gt = loadGt00();
  ASSERT_EQ(gt.size(), 4541u);
  const Poses est = perturbIncrements(gt, [](Eigen::Isometry3d d) {
    d.translation() *= 1.01;
    return d;
  });
  const KittiMetrics m = computeKittiMetrics(gt, est);
  ASSERT_TRUE(m.valid());
  // A scaled segment is off by 1 % of its chord (start-to-end displacement), which is the path
  // length on straight stretches and shorter in turns.
  for (const auto& s : m.segments) {
    const double chord = (gt[s.last_frame].translation() - gt[s.first_frame].translation()).norm();
    ASSERT_NEAR(s.t_err, 0.01 * chord / s.length, 1e-6);
  }
  EXPECT_NEAR(m.r_err_deg_per_100m, 0.0, 1e-4);
  // On 100 m segments (mostly straight) t_err is close to the 1 % scale error.
  const KittiMetrics short_segments = computeKittiMetrics(gt, est, {100});
  EXPECT_NEAR(short_segments.t_err_percent, 1.0, 0.1);
}

TEST_F(KittiGtProperty, YawDriftPerMetre) {
  const Poses gt = loadGt00();
  const double rad_per_m = 1.0 * M_PI / 180.0 / 100.0;  // 1 deg / 100 m
  const Poses est = perturbIncrements(gt, [&](Eigen::Isometry3d d) {
    const double yaw = rad_per_m * d.translation().norm();
    d.linear() = d.linear() * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).matrix();
    return d;
  });
  const KittiMetrics m = computeKittiMetrics(gt, est);
  ASSERT_TRUE(m.valid());
  EXPECT_NEAR(m.r_err_deg_per_100m, 1.0, 0.02);
}

TEST_F(KittiGtProperty, IdenticalTrajectoryHasNoError) {
  const Poses gt = loadGt00();
  const KittiMetrics m = computeKittiMetrics(gt, gt);
  EXPECT_EQ(m.per_length.front().segments, 455u - 10u);  // nearly all first frames qualify
  EXPECT_NEAR(m.t_err_percent, 0.0, 1e-9);
}

}  // namespace
}  // namespace socc::eval
