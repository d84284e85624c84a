#pragma once
// Which Velodyne model a stream comes from, from the packets themselves: the block flags (one
// bank, upper/lower, four banks), dual-return pairs, the time between packets (sensor stamps)
// and the azimuth advance within and between packets, which together fix the number of lasers
// per firing sequence. The factory byte is only a hint: some firmware sends a wrong one.
#include <string>
#include <vector>

#include "socc/sensors/packet.hpp"
#include "velodyne_model.hpp"

namespace socc::sensors::velodyne {

struct Detection {
  const ModelInfo* model = nullptr;
  bool dual = false;
  std::string note;  // e.g. the factory byte disagreed; empty when nothing to report
};

/// Decides the model from the first data packets (1206 bytes each, one sensor, in order).
/// configured: the model the user named, or nullptr to detect it. Throws std::runtime_error
/// with the measured facts when the packets contradict the configured model or fit no model.
Detection detectModel(const std::vector<Packet>& packets, const ModelInfo* configured);

}  // namespace socc::sensors::velodyne
