// socc-sim's attitude sensor (--imu): the written up direction scatters around the true one
// with the stated sigma per tilt axis, its white part and its bias behave as modelled, and it is
// deterministic per seed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "socc/sim/attitude_sensor.hpp"

namespace socc::sim {
namespace {

// A car-like attitude at time t: yawing, pitching and rolling by a few degrees.
Eigen::Matrix3d attitudeAt(double t) {
  return (Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(0.05 * std::sin(0.7 * t), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.03 * std::cos(1.3 * t), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// The tilt of `measured` against the true up of `attitude`, in two axes perpendicular to it [rad].
Eigen::Vector2d tilt(const Eigen::Matrix3d& attitude, const Eigen::Vector3d& measured) {
  const Eigen::Vector3d up = attitude.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d e1 = up.unitOrthogonal();
  const Eigen::Vector3d e2 = up.cross(e1);
  const Eigen::Vector3d axis = up.cross(measured);  // |axis| = sin(angle)
  return {axis.dot(e1), axis.dot(e2)};
}

double rms(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x * x;
  return std::sqrt(sum / static_cast<double>(v.size()));
}

TEST(AttitudeSensor, Presets) {
  EXPECT_FALSE(imuPreset("none").any());
  const double deg = M_PI / 180.0;
  EXPECT_NEAR(imuPreset("ins").sigma(), std::sqrt(3.0) * 0.02 * deg, 1e-12);
  EXPECT_NEAR(imuPreset("mems").sigma(), std::sqrt(0.06) * deg, 1e-12);
  EXPECT_THROW(imuPreset("gyro"), std::invalid_argument);
}

// Across 2000 sensor instances (each its own misalignment, bias and noise) the error of a
// reading has the stated sigma on each tilt axis, and the reading is a unit vector.
TEST(AttitudeSensor, ErrorHasTheStatedSigmaPerTiltAxis) {
  for (const char* name : {"ins", "mems"}) {
    SCOPED_TRACE(name);
    const ImuErrors errors = imuPreset(name);
    std::vector<double> components;
    for (std::uint64_t seed = 1; seed <= 2000; ++seed) {
      AttitudeSensor sensor(errors, seed, seed + 7);
      const double t = 0.1 * static_cast<double>(seed);
      const GravityReference g = sensor.measure(attitudeAt(t), t);
      ASSERT_NEAR(g.up.norm(), 1.0, 1e-12);
      EXPECT_DOUBLE_EQ(g.sigma, errors.sigma());
      const Eigen::Vector2d e = tilt(attitudeAt(t), g.up);
      components.push_back(e.x());
      components.push_back(e.y());
    }
    // 4000 samples: the RMS is within ~1.1 % (1 sigma) of the true value.
    EXPECT_NEAR(rms(components) / errors.sigma(), 1.0, 0.05);
  }
}

// Along one drive (2000 frames at 10 Hz): frame-to-frame changes are the white part (the bias
// moves little in 0.1 s), and the mean error is the fixed misalignment plus a slow bias.
TEST(AttitudeSensor, WhiteNoiseAndSlowBiasAlongOneDrive) {
  const ImuErrors errors = imuPreset("mems");
  AttitudeSensor sensor(errors, 3, 3);
  std::vector<double> steps;
  Eigen::Vector2d previous = Eigen::Vector2d::Zero();
  for (int k = 0; k < 2000; ++k) {
    const double t = 0.1 * k;
    // A fixed attitude keeps the tilt axes fixed, so differences are the sensor's alone.
    const Eigen::Vector2d e = tilt(attitudeAt(0.0), sensor.measure(attitudeAt(0.0), t).up);
    if (k > 0) {
      steps.push_back(e.x() - previous.x());
      steps.push_back(e.y() - previous.y());
    }
    previous = e;
  }
  // Difference of two white draws: sqrt(2) x white; the bias step adds sqrt(2 (1 - e^(-0.1/30)))
  // x bias = 0.08 x bias in quadrature, 0.7 % more here.
  const double white = errors.white_deg * M_PI / 180.0;
  EXPECT_NEAR(rms(steps) / (std::sqrt(2.0) * white), 1.0, 0.06);
}

TEST(AttitudeSensor, DeterministicPerSeed) {
  const ImuErrors errors = imuPreset("ins");
  AttitudeSensor a(errors, 11, 4), b(errors, 11, 4), c(errors, 12, 4), d(errors, 11, 5);
  for (int k = 0; k < 5; ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector3d ua = a.measure(attitudeAt(t), t).up;
    EXPECT_EQ(ua, b.measure(attitudeAt(t), t).up);
    EXPECT_NE(ua, c.measure(attitudeAt(t), t).up);  // other noise
    EXPECT_NE(ua, d.measure(attitudeAt(t), t).up);  // other mounting
  }
}

}  // namespace
}  // namespace socc::sim
