#pragma once
// The attitude sensor beside the LiDAR (socc-sim --imu): an INS or an IMU with an attitude filter
// reports the up direction (opposite to gravity; the sim's world has gravity along -z) in the
// LiDAR frame, rotated away from the true one by white noise, a slowly varying bias (first-order
// Gauss-Markov) and the fixed misalignment of the IMU's mounting against the LiDAR.
// sim/README.md "Attitude sensor" gives the presets' magnitudes and their sources.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "socc/gravity_reference.hpp"
#include "socc/sim/random.hpp"

namespace socc::sim {

/// Per-axis 1-sigma magnitudes [deg] of the three error terms (small rotations, each of its
/// three components independent): the up direction's two tilt components each get their sum.
struct ImuErrors {
  double white_deg = 0.0;          // independent per frame
  double bias_deg = 0.0;           // stationary sigma of the Gauss-Markov bias
  double bias_correlation = 30.0;  // [s] its correlation time
  double misalignment_deg = 0.0;   // fixed per sensor instance (IMU mounting against the LiDAR)

  bool any() const { return white_deg > 0 || bias_deg > 0 || misalignment_deg > 0; }
  /// The stated 1-sigma of the written direction [rad]: the three terms combined.
  double sigma() const;
};

/// "none", "ins" (an OxTS RT3003-class INS, as on KITTI's car) or "mems" (a MEMS IMU with an
/// attitude filter, as built into Ouster/Hesai sensors). Throws std::invalid_argument.
ImuErrors imuPreset(const std::string& name);

class AttitudeSensor {
 public:
  /// White noise and bias from seed, the misalignment from sensor_seed (the sensor instance);
  /// both are streams of their own, so the scans do not change with the IMU.
  AttitudeSensor(const ImuErrors& errors, std::uint64_t seed, std::uint64_t sensor_seed);

  /// The reported up direction for the true attitude world_R_sensor at time t [s]; call with
  /// increasing t (the bias evolves from the previous call).
  GravityReference measure(const Eigen::Matrix3d& world_R_sensor, double t);

 private:
  Eigen::Vector3d gaussian3(Random& rng, double sigma);

  ImuErrors errors_;
  Random noise_;
  Eigen::Vector3d misalignment_;  // rotation vector [rad], sensor frame
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  double last_t_ = 0.0;
  bool started_ = false;
};

}  // namespace socc::sim
