#pragma once
// The car body on its suspension: pitch with braking and accelerating, roll in turns, and the
// oscillations of a real road (body bounce at 1-2 Hz, wheel hop and vibration at 8-15 Hz), as
// an offset on top of the route's smooth pose. The sensor (and so the ground truth) moves with
// it, so a sweep is no longer swept at constant velocity.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "socc/sim/realism.hpp"

namespace socc::sim {

class BodyMotion {
 public:
  BodyMotion(const MotionErrors& errors, std::uint64_t seed);

  /// The sensor's pose offset (in the sensor frame) at time t, for the route's acceleration in
  /// the sensor frame [m/s^2] and its speed [m/s].
  Eigen::Isometry3d offset(double t, const Eigen::Vector3d& acceleration, double speed) const;

 private:
  struct Wave {
    double amplitude;  // [rad] or [m]
    double frequency;  // [Hz]
    double phase;      // [rad]
  };
  static double sum(const std::array<Wave, 4>& waves, double t);

  MotionErrors errors_;
  std::array<Wave, 4> pitch_{};
  std::array<Wave, 4> roll_{};
  std::array<Wave, 4> heave_{};
};

}  // namespace socc::sim
