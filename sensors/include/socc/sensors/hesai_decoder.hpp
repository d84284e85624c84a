#pragma once
// Hesai PandarXT32, Pandar40P and Pandar64 packets -> sweeps (docs/sensors_ouster_hesai.md).
// makeDecoder (sensor_config.hpp) dispatches here for these model names.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors {

/// pandarxt32, pandar40p, pandar64.
std::vector<std::string> hesaiModels();
bool isHesaiModel(const std::string& model);

/// The Hesai model whose packet layout payload has (size and header counts agree), or "".
std::string detectHesaiModel(const std::vector<std::uint8_t>& payload);

/// A decoder for config.model with config.calibration (the angle-correction CSV; empty: the
/// PandarXT32's nominal angles, the others need their file). Throws std::runtime_error on an
/// unknown model or a bad calibration file. Its feed() throws std::runtime_error when the
/// stream holds packets of another model only (never decoding garbage from them).
std::unique_ptr<ScanDecoder> makeHesaiDecoder(const SensorConfig& config);

}  // namespace socc::sensors
