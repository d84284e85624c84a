#pragma once
// Spinning multi-beam LiDAR models. A sweep takes `sweep_period`; column c fires at time
// c / columns * sweep_period, looking at azimuth pi - 2 pi c / columns (it starts facing
// backwards and turns clockwise seen from above, like a Velodyne).
#include <string>
#include <vector>

namespace socc::sim {

struct LidarModel {
  std::string name;
  std::vector<double> elevations_deg;  // one per beam
  int columns = 0;
  double sweep_period = 0.1;  // [s]
  double min_range = 0.5;     // [m]
  double max_range = 100.0;   // [m]
  double range_noise = 0.0;   // gaussian sigma [m]
  double dropout = 0.0;       // probability that a return is lost

  double columnTime(int column) const { return sweep_period * column / columns; }
  double columnAzimuth(int column) const;
};

/// "hdl64" (KITTI: 64 beams +2..-24.9 deg, 2000 columns), "vlp32" (32 beams +15..-25 deg, 1800
/// columns), "vlp16" (16 beams +-15 deg, 1800 columns). Throws std::invalid_argument otherwise.
LidarModel lidarPreset(const std::string& name);

}  // namespace socc::sim
