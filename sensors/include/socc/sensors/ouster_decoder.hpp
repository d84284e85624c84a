#pragma once
// Ouster OS0 / OS1 / OS2 lidar packets -> frames (docs/sensors_ouster_hesai.md), configured
// from the sensor's metadata JSON. makeDecoder (sensor_config.hpp) dispatches here for the
// model names os0-*, os1-*, os2-* (16, 32, 64 or 128 beams).
#include <memory>
#include <string>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors {

/// os0-16 ... os2-128 (also "ouster": the model the metadata names).
bool isOusterModel(const std::string& model);

/// A decoder configured by config.calibration (the metadata JSON, required). Throws
/// std::runtime_error on a missing or bad metadata file, or when config.model names another
/// model than the metadata. Frames are the sensor's own (frame id); cut_azimuth_deg does not
/// apply. Its feed() throws std::runtime_error when the stream holds lidar packets of another
/// format or sensor only (wrong metadata), never decoding them.
std::unique_ptr<ScanDecoder> makeOusterDecoder(const SensorConfig& config);

}  // namespace socc::sensors
