// TEMPORARY, for this branch alone: makeDecoder / supportedModels are implemented on the
// velodyne branch. Until it is merged, test_bags links this stand-in, which knows no model.
// DELETE this file and its line in tests/sensors/CMakeLists.txt when merging.
#include <stdexcept>

#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors {

std::unique_ptr<ScanDecoder> makeDecoder(const SensorConfig& config) {
  throw std::runtime_error("makeDecoder stub: no decoder for '" + config.model + "'");
}

std::vector<std::string> supportedModels() {
  return {};
}

}  // namespace socc::sensors
