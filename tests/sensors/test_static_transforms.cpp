// StaticTransforms: chains of mounts used in either direction, frame names with and without a
// leading '/', a child's later transform replacing its earlier one, and no answer without a chain.
#include <gtest/gtest.h>

#include "socc/sensors/static_transforms.hpp"

namespace socc::sensors {
namespace {

Eigen::Isometry3d pose(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = t;
  return p;
}

TEST(StaticTransforms, ChainsJoinFramesEitherWay) {
  StaticTransforms mounts;
  const Eigen::Isometry3d base_T_lidar = pose(0.3, {1, 0, 2});
  const Eigen::Isometry3d base_T_mast = pose(-0.2, {0, 1, 1});
  const Eigen::Isometry3d mast_T_imu = pose(1.0, {0.1, 0.2, 0.3});
  mounts.add("/base_link", "lidar", base_T_lidar);
  mounts.add("base_link", "/mast", base_T_mast);
  mounts.add("mast", "imu", mast_T_imu);
  const Eigen::Isometry3d want = base_T_lidar.inverse() * base_T_mast * mast_T_imu;
  ASSERT_TRUE(mounts.lookup("lidar", "imu"));
  EXPECT_TRUE(mounts.lookup("lidar", "imu")->isApprox(want, 1e-12));
  EXPECT_TRUE(mounts.lookup("/imu", "/lidar")->isApprox(want.inverse(), 1e-12));
  EXPECT_TRUE(mounts.lookup("imu", "imu")->isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(mounts.lookup("lidar", "camera"));
  EXPECT_FALSE(StaticTransforms().lookup("lidar", "imu"));

  mounts.add("base_link", "lidar", Eigen::Isometry3d::Identity());  // re-published: replaces
  EXPECT_TRUE(mounts.lookup("lidar", "imu")->isApprox(base_T_mast * mast_T_imu, 1e-12));
  EXPECT_EQ(mounts.describe(), "  base_link -> lidar\n  base_link -> mast\n  mast -> imu\n");
}

}  // namespace
}  // namespace socc::sensors
