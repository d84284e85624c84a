#pragma once
// A keyframe's gravity reference (docs/consistency.md "Gravity reference"): the up direction
// (opposite to gravity) in the sensor frame at the scan's time, from the robot's IMU or INS
// attitude, and the standard deviation of its direction. The pose graph ties the keyframe's
// attitude to the map frame's up direction with it (pose_graph.hpp, GravityPrior): the one
// measurement of a tilt of the whole map, which no loop closure observes.
#include <Eigen/Core>
#include <optional>

namespace socc::consistency {

struct GravityReference {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // unit vector, sensor frame
  double sigma = 0.0;                             // [rad] 1-sigma of its direction, > 0
};

/// The reference an INTEGRATE carries (gravity_up, gravity_sigma; docs/lcm.md): none when sigma
/// is not > 0 (0: the robot has none) or up is not a finite nonzero vector; up normalized.
std::optional<GravityReference> gravityReference(const Eigen::Vector3d& up, double sigma);

}  // namespace socc::consistency
