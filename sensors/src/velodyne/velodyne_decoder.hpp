#pragma once
// The Velodyne ScanDecoder (VLP-16, VLP-32C, HDL-32E, HDL-64E S2/S3, VLS-128). Programs get it
// through makeDecoder (sensor_config.hpp).
#include <memory>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors::velodyne {

/// config.model: a Velodyne model name, or empty to detect it from the first packets. Throws
/// std::runtime_error on an unknown model, a bad calibration file or an unsupported return mode.
std::unique_ptr<ScanDecoder> makeVelodyneDecoder(const SensorConfig& config);

}  // namespace socc::sensors::velodyne
