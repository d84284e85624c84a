// Hand-computed ATE and RPE cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "socc/eval/absolute_trajectory_error.hpp"
#include "socc/eval/evaluation.hpp"
#include "socc/eval/relative_pose_error.hpp"

namespace socc::eval {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw = 0.0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).matrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

Poses circle(std::size_t n) {
  Poses poses;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    poses.push_back(pose(10 * std::cos(a), 10 * std::sin(a), 0.1 * a, a + M_PI / 2));
  }
  return poses;
}

TEST(AbsoluteTrajectoryError, RigidOffsetIsAlignedAway) {
  const Poses gt = circle(100);
  Eigen::Isometry3d offset = pose(5, -3, 2, 0.7);
  offset.rotate(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  Poses est;
  for (const auto& p : gt) est.push_back(offset * p);
  const AbsoluteTrajectoryError ate = computeAbsoluteTrajectoryError(gt, est);
  EXPECT_LT(ate.stats.max, 1e-9);
  EXPECT_TRUE(ate.alignment.isApprox(offset.inverse(), 1e-9));
  // Without the alignment the offset is the error.
  double farthest = 0.0;
  for (std::size_t i = 0; i < gt.size(); ++i)
    farthest = std::max(farthest, (gt[i].translation() - est[i].translation()).norm());
  EXPECT_NEAR(ate.unaligned.max, farthest, 1e-9);
  EXPECT_GT(ate.unaligned.min, 1.0);
}

TEST(AbsoluteTrajectoryError, AlternatingNoiseGivesItsRms) {
  // Pairs of frames at the same ground-truth position, estimated +d and -d off in z: no rigid
  // transform can do better than identity, and every error is d.
  const double d = 0.3;
  Poses gt;
  Poses est;
  const Poses base = circle(50);
  for (const auto& p : base) {
    for (const double sign : {1.0, -1.0}) {
      gt.push_back(p);
      Eigen::Isometry3d e = p;
      e.translation().z() += sign * d;
      est.push_back(e);
    }
  }
  const AbsoluteTrajectoryError ate = computeAbsoluteTrajectoryError(gt, est);
  EXPECT_NEAR(ate.stats.rmse, d, 1e-9);
  EXPECT_NEAR(ate.stats.mean, d, 1e-9);
  EXPECT_NEAR(ate.stats.std, 0.0, 1e-9);
}

TEST(AbsoluteTrajectoryError, SizeMismatchThrows) {
  EXPECT_THROW(computeAbsoluteTrajectoryError(circle(10), circle(9)), std::invalid_argument);
  EXPECT_THROW(computeAbsoluteTrajectoryError({}, {}), std::invalid_argument);
}

TEST(RelativePoseError, KnownPerStepErrors) {
  // GT moves 1 m per frame along x; the estimate moves 1.1 m, then 0.8 m, and yaws 2 deg once.
  const Poses gt = {pose(0, 0, 0), pose(1, 0, 0), pose(2, 0, 0)};
  const double yaw = 2.0 * M_PI / 180.0;
  const Poses est = {pose(0, 0, 0), pose(1.1, 0, 0, yaw),
                     pose(1.1 + 0.8 * std::cos(yaw), 0.8 * std::sin(yaw), 0, yaw)};
  const RelativePoseError rpe = computeRelativePoseError(gt, est);
  ASSERT_EQ(rpe.translation_errors.size(), 2u);
  EXPECT_NEAR(rpe.translation_errors[0], 0.1, 1e-12);
  EXPECT_NEAR(rpe.translation_errors[1], 0.2, 1e-12);
  EXPECT_NEAR(rpe.rotation_errors[0], 2.0, 1e-9);
  EXPECT_NEAR(rpe.rotation_errors[1], 0.0, 1e-9);
  EXPECT_NEAR(rpe.translation.mean, 0.15, 1e-12);
  EXPECT_NEAR(rpe.translation.rmse, std::sqrt((0.01 + 0.04) / 2), 1e-12);
  EXPECT_NEAR(rpe.translation.max, 0.2, 1e-12);
}

TEST(Evaluation, JsonHasAllMetrics) {
  const Poses gt = circle(200);
  const Evaluation e = evaluate(gt, gt, {{10.0, 20.0}, 10});
  const nlohmann::json j = toJson(e);
  EXPECT_EQ(j["frames"], 200);
  EXPECT_NEAR(j["kitti"]["t_err_percent"].get<double>(), 0.0, 1e-9);
  for (const char* key : {"ate_m", "rpe_trans_m", "rpe_rot_deg"})
    for (const char* stat : {"mean", "median", "max", "rmse", "std"})
      EXPECT_TRUE(j[key].contains(stat)) << key << "." << stat;
}

}  // namespace
}  // namespace socc::eval
