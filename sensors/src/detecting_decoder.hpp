#pragma once
// The decoder of a stream whose model is not configured: it looks at the first data packet and
// hands the stream to the family whose layout that packet has (Hesai by its header and size,
// cross-checked in detectHesaiModel; otherwise Velodyne, which detects its model from packet
// timing and azimuth steps itself). Ouster needs its metadata JSON, so it is never guessed.
#include <functional>
#include <memory>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors {

std::unique_ptr<ScanDecoder> makeDetectingDecoder(const SensorConfig& config);

}  // namespace socc::sensors
