#include <gtest/gtest.h>

#include <cmath>

#include "correction_fit.hpp"

namespace socc::consistency {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw, double pitch = 0.0) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

TEST(CorrectionFit, OneRigidCorrectionOfAllSamplesIsFoundExactly) {
  const Eigen::Isometry3d truth = pose(3.0, -2.0, 0.4, 0.05, 0.01);
  std::vector<CorrectionSample> samples;
  for (int i = 0; i < 10; ++i) {  // a straight stretch far from the origin
    const Eigen::Isometry3d raw = pose(400.0 + 3.0 * i, 250.0, 1.0, 0.3);
    samples.push_back({raw, truth * raw});
  }
  const Eigen::Isometry3d fit = fitCorrection(samples);
  EXPECT_TRUE(fit.isApprox(truth, 1e-9)) << fit.matrix();
}

TEST(CorrectionFit, TheChainsFreeEndDoesNotDecideTheCorrection) {
  // Ten keyframes corrected alike, the last one 0.55 m higher (the end of the chain, held by
  // one odometry edge): the grid around the robot is made of the ten, so the robot's correction
  // must move it with them, not with the last keyframe alone.
  const Eigen::Isometry3d common = pose(1.0, 0.5, 0.0, 0.01);
  std::vector<CorrectionSample> samples;
  for (int i = 0; i < 10; ++i) {
    const Eigen::Isometry3d raw = pose(100.0 + 3.0 * i, 50.0, 0.0, 0.0);
    samples.push_back({raw, common * raw});
  }
  const Eigen::Isometry3d last_raw = pose(130.0, 50.0, 0.0, 0.0);
  samples.push_back({last_raw, pose(0.0, 0.0, 0.55, 0.0) * common * last_raw});
  const Eigen::Isometry3d fit = fitCorrection(samples);
  // At the robot (the last keyframe's raw position): 0.05 m above where the ten put it, not 0.55.
  const Eigen::Vector3d at_robot = fit * last_raw.translation();
  const Eigen::Vector3d with_the_ten = common * last_raw.translation();
  EXPECT_NEAR((at_robot - with_the_ten).norm(), 0.55 / 11.0, 1e-6);
}

TEST(CorrectionFit, NoSampleIsTheIdentity) {
  EXPECT_TRUE(fitCorrection({}).isApprox(Eigen::Isometry3d::Identity()));
}

}  // namespace
}  // namespace socc::consistency
