#pragma once
// Per-frame health of a registration: is the estimate trustworthy enough to enter the shared
// map? Judged from the registration's own evidence (inlier fraction, residual against sigma, how
// well each direction is constrained). The motion it implies (speed, acceleration over the scans'
// time stamps) is only reported: a robot may move in ways no limit foresaw, and where the input
// has no time stamps the frame period is assumed, so a kinematic limit alone is no evidence that
// the registration is wrong. Only where the registration is weak (degenerate) does a kinematic
// surprise make the frame unhealthy: there the motion model is the only evidence left.
#include <string>

#include "socc/odom/odom_config.hpp"
#include "socc/odom/registration.hpp"
#include "socc/odom/se3.hpp"

namespace socc::odom {

struct FrameHealth {
  double inlier_fraction = 1.0;  // correspondences / registered points
  double residual_ratio = 0.0;   // RMS residual / sigma
  // Planar correspondences (weighted) that constrain the least constrained direction of
  // translation, and that direction (map frame). Point-to-point pairs do not count: a pair
  // with a voxel's first point seems to pin every direction, also along a featureless wall.
  double weakest_constraint = 0.0;
  Eigen::Vector3d weakest_direction = Eigen::Vector3d::Zero();
  double linear_speed = 0.0;          // [m/s]
  double angular_speed = 0.0;         // [rad/s]
  double linear_acceleration = 0.0;   // [m/s^2]
  double angular_acceleration = 0.0;  // [rad/s^2]
  bool degenerate = false;  // a direction is barely constrained (flagged; not unhealthy alone)
  std::string surprise;     // a kinematic limit the motion exceeds (reported); empty when none
  std::string problem;      // why the frame is unhealthy; empty when healthy

  bool healthy() const { return problem.empty(); }
};

/// Judges the registration of `points` registered points at threshold sigma.
FrameHealth judgeRegistration(const RegistrationResult& r, std::size_t points, double sigma,
                              const OdomConfig& limits);

/// Adds the motion check: twist [per second] is the estimated motion since the previous frame,
/// dt [s] apart; previous_twist the one before (nullptr: unknown, acceleration not judged).
/// A limit exceeded is a surprise (reported), unhealthy only when the frame is degenerate.
void judgeMotion(FrameHealth& health, const Vector6d& twist, const Vector6d* previous_twist,
                 double dt, const OdomConfig& limits);

}  // namespace socc::odom
