#pragma once
// A keyframe's gravity reference (docs/consistency.md "Gravity reference"): the up direction
// (opposite to gravity) in the sensor frame at the scan's time, from the robot's IMU or INS
// attitude, and the standard deviation of its direction. The pose graph ties the keyframe's
// attitude to the map frame's up direction with it (pose_graph.hpp, GravityPrior): the one
// measurement of a tilt of the whole map, which no loop closure observes.
#include <Eigen/Core>
#include <optional>

#include "socc/gravity_reference.hpp"

namespace socc::consistency {

using socc::GravityReference;  // the client's type: up (sensor frame), sigma per tilt axis

/// The reference an INTEGRATE carries (gravity_up, gravity_sigma; docs/lcm.md): none when sigma
/// is not > 0 (0: the robot has none) or up is not a finite nonzero vector; up normalized.
std::optional<GravityReference> gravityReference(const Eigen::Vector3d& up, double sigma);

}  // namespace socc::consistency
