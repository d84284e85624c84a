#pragma once
// One sensor per stream: several LiDARs may send to one UDP port (and a capture may hold them
// all). A stream decodes the packets of one sender, SensorConfig::sensor_address or else the
// first sender whose packet its decoder takes; every other sender's packets are dropped before
// decoding (never mixed into a sweep), counted and reported once per address. makeDecoder puts
// this in front of every decoder.
#include <cstdint>
#include <memory>
#include <string>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"

namespace socc::sensors {

/// The IPv4 address text ("192.168.1.201") in host byte order; throws std::runtime_error naming
/// the text when it is not one.
std::uint32_t parseSensorAddress(const std::string& text);

/// "192.168.1.201".
std::string formatIpv4(std::uint32_t address);

/// inner, fed with the packets of config.sensor_address (or of the first sender it takes) only.
std::unique_ptr<ScanDecoder> selectSender(const SensorConfig& config,
                                          std::unique_ptr<ScanDecoder> inner);

}  // namespace socc::sensors
