// Velodyne calibration files (VeloView XML, ROS YAML) on arbitrary content: the first byte picks
// the format; loading must return or throw std::runtime_error.
#include <stdexcept>

#include "socc/sensors/velodyne_calibration.hpp"
#include "temp_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const socc::fuzz::TempFile file(data + 1, size - 1, data[0] % 2 == 0 ? ".xml" : ".yaml");
  try {
    socc::sensors::velodyne::loadCalibration(file.path());
  } catch (const std::runtime_error&) {
  }
  return 0;
}
