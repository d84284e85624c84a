#include "socc/sim/attitude_sensor.hpp"

#include <cmath>
#include <stdexcept>

namespace socc::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
// Streams of the attitude sensor, apart from every stream the scans use.
constexpr std::uint64_t kNoiseStream = 0x1A77'17DE'0000'0001ull;
constexpr std::uint64_t kMountStream = 0x1A77'17DE'0000'0002ull;

double gaussian(Random& rng) {
  const double u1 = rng.uniform();
  const double u2 = rng.uniform();
  return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

double ImuErrors::sigma() const {
  return kDeg * std::sqrt(white_deg * white_deg + bias_deg * bias_deg +
                          misalignment_deg * misalignment_deg);
}

// The figures and their sources are in sim/README.md ("Attitude sensor").
ImuErrors imuPreset(const std::string& name) {
  if (name == "none") return {0.0, 0.0, 30.0, 0.0};
  if (name == "ins") return {0.02, 0.02, 30.0, 0.02};
  if (name == "mems") return {0.1, 0.2, 30.0, 0.1};
  throw std::invalid_argument("unknown IMU '" + name + "' (none, ins, mems)");
}

AttitudeSensor::AttitudeSensor(const ImuErrors& errors, std::uint64_t seed,
                               std::uint64_t sensor_seed)
    : errors_(errors), noise_(splitMix64(seed ^ kNoiseStream)) {
  Random mount(splitMix64(sensor_seed ^ kMountStream));
  misalignment_ = gaussian3(mount, errors_.misalignment_deg * kDeg);
  bias_ = gaussian3(noise_, errors_.bias_deg * kDeg);  // stationary from the start
}

Eigen::Vector3d AttitudeSensor::gaussian3(Random& rng, double sigma) {
  const double x = gaussian(rng);
  const double y = gaussian(rng);
  const double z = gaussian(rng);
  return sigma * Eigen::Vector3d(x, y, z);
}

GravityReference AttitudeSensor::measure(const Eigen::Matrix3d& world_R_sensor, double t) {
  if (started_) {
    // First-order Gauss-Markov: exact discretization, stationary sigma bias_deg.
    const double phi = std::exp(-std::max(t - last_t_, 0.0) / errors_.bias_correlation);
    bias_ = phi * bias_ + gaussian3(noise_, std::sqrt(1.0 - phi * phi) * errors_.bias_deg * kDeg);
  }
  started_ = true;
  last_t_ = t;
  const Eigen::Vector3d error = gaussian3(noise_, errors_.white_deg * kDeg) + bias_ + misalignment_;
  const Eigen::Vector3d true_up = world_R_sensor.transpose() * Eigen::Vector3d::UnitZ();
  const double angle = error.norm();
  const Eigen::Vector3d up =
      angle > 0.0 ? Eigen::AngleAxisd(angle, error / angle) * true_up : true_up;
  return {up.normalized(), errors_.sigma()};
}

}  // namespace socc::sim
