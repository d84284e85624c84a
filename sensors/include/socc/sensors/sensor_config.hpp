#pragma once
// Which sensor a packet stream comes from and how to decode it, and the one factory of
// decoders. Model names: vlp16, vlp32c, hdl32e, hdl64e, vls128 (Velodyne), os0-*/os1-*/os2-*
// (Ouster, e.g. os1-128), pandarxt32, pandar40p, pandar64 (Hesai); docs/sensors.md.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "socc/sensors/scan_decoder.hpp"

namespace socc::sensors {

enum class ReturnMode { kAll, kStrongest, kLast, kFirst };

struct SensorConfig {
  std::string
      model;  // empty: detected from the packets (cross-checked, never the factory byte alone)
  // VeloView XML or ROS velodyne YAML; Ouster metadata JSON; Hesai angle-correction CSV.
  // Empty: the model's nominal values from its manual, where the model has them.
  std::filesystem::path calibration;
  double cut_azimuth_deg = 0.0;  // a sweep ends where the azimuth crosses this [deg]
  ReturnMode returns = ReturnMode::kAll;
  double min_range = 0.0;     // [m] closer returns are dropped (0: the model's own minimum)
  double max_range = 0.0;     // [m] 0: no limit
  bool keep_partial = false;  // keep the first / last incomplete sweep (complete == false)
  // The sensor's IPv4 address (pcap, live UDP: several sensors on one port). Empty: the first
  // sender whose packets the decoder takes. Packets of every other sender are dropped, counted
  // (DecodeStats::other_sender) and reported once per address.
  std::string sensor_address;
  // Told at once what the user must know while a run goes on (a second sender on the port);
  // empty: written to std::cerr. The end-of-run summary (notes()) repeats it.
  std::function<void(const std::string&)> notify;
};

/// A decoder for config.model (or one that detects the model from the first packets) that
/// decodes the packets of one sender (config.sensor_address, or the first). Throws
/// std::runtime_error with a clear message on an unknown model, a bad calibration or a bad
/// address.
std::unique_ptr<ScanDecoder> makeDecoder(const SensorConfig& config);

/// The model names makeDecoder accepts, for --help and error messages.
std::vector<std::string> supportedModels();

}  // namespace socc::sensors
