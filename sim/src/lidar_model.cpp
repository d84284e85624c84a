#include "socc/sim/lidar_model.hpp"

#include <cmath>
#include <stdexcept>

namespace socc::sim {

namespace {

std::vector<double> evenlySpaced(double top, double bottom, int beams) {
  std::vector<double> e;
  for (int i = 0; i < beams; ++i) e.push_back(top + (bottom - top) * i / (beams - 1));
  return e;
}

}  // namespace

double LidarModel::columnAzimuth(int column) const {
  return M_PI - 2.0 * M_PI * static_cast<double>(column) / columns;
}

LidarModel lidarPreset(const std::string& name) {
  LidarModel m;
  m.name = name;
  if (name == "hdl64") {
    m.elevations_deg = evenlySpaced(2.0, -24.9, 64);
    m.columns = 2000;
  } else if (name == "vlp32") {
    m.elevations_deg = evenlySpaced(15.0, -25.0, 32);
    m.columns = 1800;
  } else if (name == "vlp16") {
    m.elevations_deg = evenlySpaced(15.0, -15.0, 16);
    m.columns = 1800;
  } else {
    throw std::invalid_argument("unknown sensor '" + name + "' (hdl64, vlp32, vlp16)");
  }
  return m;
}

}  // namespace socc::sim
