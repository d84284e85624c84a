#pragma once
// Flat ground and four vertical walls, seen as ray ranges: the scene of the odometry's sensor
// calibration tests (test_elevation_correction.cpp, test_range_calibration.cpp). Named
// namespace, inline: test_odom is a unity build.
#include <Eigen/Core>

namespace socc::odom_test {

struct WalledGround {
  double ground_z;                    // [m] in the frame of the rays' origins
  double x_min, x_max, y_min, y_max;  // [m] the walls
};

/// Range from origin along the unit direction d to the first surface of world beyond 0.5 m;
/// negative: no hit.
inline double rangeTo(const WalledGround& world, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& d) {
  double best = -1.0;
  const auto take = [&](double t) {
    if (t > 0.5 && (best < 0.0 || t < best)) best = t;
  };
  if (d.z() < 0.0) take((world.ground_z - origin.z()) / d.z());
  if (d.x() != 0.0) {
    take((world.x_max - origin.x()) / d.x());
    take((world.x_min - origin.x()) / d.x());
  }
  if (d.y() != 0.0) {
    take((world.y_max - origin.y()) / d.y());
    take((world.y_min - origin.y()) / d.y());
  }
  return best;
}

}  // namespace socc::odom_test
