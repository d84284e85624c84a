#pragma once
// A scan's gravity reference: the up direction (opposite to gravity) in the sensor frame at the
// scan's time, from an IMU's or INS's attitude, with the 1-sigma of its direction
// (docs/lcm.md "Gravity reference").
#include <Eigen/Core>

namespace socc {

struct GravityReference {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // unit vector, sensor frame
  double sigma = 0.0;  // [rad] 1-sigma of each of its two tilt components (roll, pitch), > 0
};

}  // namespace socc
