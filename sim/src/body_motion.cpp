#include "socc/sim/body_motion.hpp"

#include <algorithm>
#include <cmath>

#include "socc/sim/random.hpp"

namespace socc::sim {

namespace {

constexpr double kRadPerDeg = M_PI / 180.0;
constexpr double kPivotBelowSensor = 1.2;  // [m] pitch/roll centre near the axles
constexpr double kFullBumpSpeed = 10.0;    // [m/s] bumps grow with speed up to this

}  // namespace

BodyMotion::BodyMotion(const MotionErrors& errors, std::uint64_t seed) : errors_(errors) {
  Random rng(splitMix64(seed ^ 0xB0D1u));
  // Two body modes (bounce/pitch, 1-2 Hz) and two vibration modes (8-15 Hz) per axis.
  const auto fill = [&](std::array<Wave, 4>& w, double body, double vibration) {
    w[0] = {0.6 * body, rng.uniform(1.0, 1.5), rng.uniform(0, 2 * M_PI)};
    w[1] = {0.4 * body, rng.uniform(1.5, 2.2), rng.uniform(0, 2 * M_PI)};
    w[2] = {0.6 * vibration, rng.uniform(8.0, 11.0), rng.uniform(0, 2 * M_PI)};
    w[3] = {0.4 * vibration, rng.uniform(11.0, 15.0), rng.uniform(0, 2 * M_PI)};
  };
  fill(pitch_, errors.bump_pitch_deg * kRadPerDeg, errors.vibration_deg * kRadPerDeg);
  fill(roll_, errors.bump_roll_deg * kRadPerDeg, errors.vibration_deg * kRadPerDeg);
  fill(heave_, errors.bump_heave, 0.0);
}

double BodyMotion::sum(const std::array<Wave, 4>& waves, double t) {
  double s = 0.0;
  for (const Wave& w : waves) s += w.amplitude * std::sin(2 * M_PI * w.frequency * t + w.phase);
  return s;
}

Eigen::Isometry3d BodyMotion::offset(double t, const Eigen::Vector3d& acceleration,
                                     double speed) const {
  const double bumps = std::min(1.0, speed / kFullBumpSpeed);
  // Braking (negative x acceleration) dives the nose (positive pitch about y turns x down);
  // a left turn (positive y acceleration) rolls the body outwards, lifting its left side.
  const double pitch =
      -errors_.pitch_per_acceleration_deg * kRadPerDeg * acceleration.x() + bumps * sum(pitch_, t);
  const double roll =
      errors_.roll_per_lateral_deg * kRadPerDeg * acceleration.y() + bumps * sum(roll_, t);
  const Eigen::Vector3d pivot(0.0, 0.0, -kPivotBelowSensor);
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  Eigen::Isometry3d o = Eigen::Isometry3d::Identity();
  o.linear() = r;
  o.translation() = pivot - r * pivot + Eigen::Vector3d(0, 0, bumps * sum(heave_, t));
  return o;
}

}  // namespace socc::sim
