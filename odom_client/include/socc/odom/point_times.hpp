#pragma once
// Per-point times for scans of a spinning sensor that carry none (e.g. KITTI): a point's time
// follows from its azimuth, the sweep's start azimuth and turning direction.
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::odom {

struct SweepGeometry {
  double period = 0.1;             // [s] one revolution
  double start_azimuth_deg = 180;  // where the sweep starts (atan2(y, x) of the sensor frame)
  bool clockwise = true;           // seen from above
  double scan_time_in_sweep = 0;   // where the scan's timestamp lies: 0 start, 0.5 middle, 1 end
};

/// One time per point [s, relative to the scan's timestamp], within
/// [-scan_time_in_sweep, 1 - scan_time_in_sweep] * period.
std::vector<float> azimuthTimes(const Points& points, const SweepGeometry& sweep);

}  // namespace socc::odom
