#include <gtest/gtest.h>

#include <cmath>

#include "socc/odom/tilt_reference.hpp"

using socc::odom::TiltPrior;
using socc::odom::TiltReference;

namespace {
constexpr double kWalk = 1e-3;   // rad / sqrt(s)
constexpr double kSigma = 2e-3;  // rad
}  // namespace

TEST(TiltReference, NoPriorBeforeTheFirstFrameOrWhenOff) {
  const TiltReference tilt(kWalk);
  EXPECT_FALSE(tilt.prior(Eigen::Vector3d::UnitZ(), kSigma, 0.0));
  TiltReference off(0.0);
  off.update(Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitZ(), kSigma, 0.0);
  EXPECT_FALSE(off.prior(Eigen::Vector3d::UnitZ(), kSigma, 0.1));
}

TEST(TiltReference, TheGainIsTheKalmanFiltersPerTiltAxis) {
  TiltReference tilt(kWalk);
  tilt.update(Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitZ(), kSigma, 0.0);
  EXPECT_EQ(tilt.variance(), 0.0);  // the first frame defines the map's up
  double p = 0.0;
  for (int k = 1; k <= 2000; ++k) {
    const double t = 0.1 * k;
    const std::optional<TiltPrior> prior = tilt.prior(Eigen::Vector3d::UnitZ(), kSigma, t);
    ASSERT_TRUE(prior);
    const double predicted = p + kWalk * kWalk * 0.1;
    ASSERT_NEAR(prior->gain, predicted / (predicted + kSigma * kSigma), 1e-12);
    p = (1.0 - prior->gain) * predicted;
    tilt.update(Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitZ(), kSigma, t);
    ASSERT_NEAR(tilt.variance(), p, 1e-15);
  }
  // Steady state of a random walk q per step seen with noise r: P^2 + qP - qr = 0 (prior side).
  const double q = kWalk * kWalk * 0.1, r = kSigma * kSigma;
  const double steady = (-q + std::sqrt(q * q + 4.0 * q * r)) / 2.0;
  EXPECT_NEAR(p, steady, 1e-3 * steady);
}

TEST(TiltReference, TheMapsUpIsTheFirstSecondsMeanAndTurnsWithTheFrame) {
  TiltReference tilt(kWalk);
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()).toRotationMatrix();
  tilt.update(Eigen::Matrix3d::Identity(), roll * Eigen::Vector3d::UnitZ(), kSigma, 0.0);
  tilt.update(Eigen::Matrix3d::Identity(), roll.transpose() * Eigen::Vector3d::UnitZ(), kSigma,
              0.1);
  std::optional<TiltPrior> prior = tilt.prior(Eigen::Vector3d::UnitZ(), kSigma, 0.2);
  ASSERT_TRUE(prior);
  EXPECT_NEAR((prior->map_up - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  const double q = kWalk * kWalk * 0.1, r = kSigma * kSigma;
  const double p = (1.0 - q / (q + r)) * q + q;  // after the second frame, predicted at 0.2 s
  EXPECT_NEAR(prior->gain, p / (p + r), 1e-12);
  // After the first second a frame's up no longer moves the map's: it carries the drift.
  tilt.update(Eigen::Matrix3d::Identity(), roll * Eigen::Vector3d::UnitZ(), kSigma, 1.2);
  prior = tilt.prior(Eigen::Vector3d::UnitZ(), kSigma, 1.3);
  EXPECT_NEAR((prior->map_up - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  tilt.moveFrame(turn);
  prior = tilt.prior(Eigen::Vector3d::UnitZ(), kSigma, 0.2);
  EXPECT_NEAR((prior->map_up - turn * Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
}
