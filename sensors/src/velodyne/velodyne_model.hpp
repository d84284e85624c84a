#pragma once
// The Velodyne models this library decodes, with the facts of their user manuals that decoding
// needs: packet layout (which laser a data point belongs to), firing timing (each point's time
// offset from the packet's time stamp), distance resolution and nominal beam angles.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "socc/sensors/velodyne_calibration.hpp"

namespace socc::sensors::velodyne {

constexpr std::size_t kPacketBytes = 1206;  // UDP payload of a data packet (every model here)
constexpr int kBlocks = 12;                 // data blocks per packet
constexpr int kChannels = 32;               // data points per block
constexpr std::size_t kBlockBytes =
    100;  // flag (2) + azimuth (2) + 32 x (distance 2, reflectivity 1)
constexpr std::size_t kStampOffset = 1200;  // uint32 microseconds past the hour
constexpr std::size_t kReturnModeOffset = 1204;
constexpr std::size_t kProductIdOffset = 1205;

enum class Family { kVlp16, kVlp32c, kHdl32e, kHdl64e, kVls128 };

/// Where one data point of a packet sits in the sensor's firing order.
struct PointSlot {
  std::uint16_t laser = 0;       // laser id (calibration index)
  float offset_us = 0.0f;        // firing time relative to the packet's time stamp
  std::uint8_t block_start = 0;  // 1 for the first point of its block
};

/// Layout and timing of one model in one return mode: 12 x 32 point slots, the flag each block
/// must carry (0: not checked), which return a block holds in dual mode, and each block's
/// firing-sequence start (the instant its azimuth field was read).
struct PacketLayout {
  std::array<std::array<PointSlot, kChannels>, kBlocks> slots{};
  std::array<std::uint16_t, kBlocks> flag{};       // 0xEEFF style, as read little-endian
  std::array<std::int8_t, kBlocks> return_slot{};  // -1 single; dual: 1 last, 0 strongest
  std::array<std::int8_t, kBlocks> partner{};      // dual: the other return's block; else -1
  std::array<float, kBlocks> block_start_us{};     // sequence start relative to the stamp
  std::array<bool, kBlocks> used{};  // false: the block carries no data (VLS-128 dual)
  double packet_period_us = 0.0;     // time between packets
  double firing_span_end_us = 0.0;   // last firing relative to the stamp
};

struct ModelInfo {
  std::string_view name;       // "vlp16"
  std::string_view full_name;  // "Velodyne VLP-16"
  Family family;
  int lasers;
  std::vector<std::uint8_t> product_ids;  // factory byte values (none for the HDL-64E)
  double distance_resolution_m;
  double sequence_us;  // one firing sequence (all lasers) [us]
  // Nominal beam angles from the manual [deg]; empty: a calibration file is required.
  std::vector<double> vert_deg;
  std::vector<double> rot_deg;  // azimuth offsets (ROS sign: beam at azimuth - rot)
};

const std::vector<ModelInfo>& velodyneModels();
/// nullptr when name is not a Velodyne model.
const ModelInfo* findVelodyneModel(std::string_view name);

PacketLayout packetLayout(const ModelInfo& model, bool dual);

/// The model's nominal calibration (manual angles); throws when the model has none.
Calibration nominalCalibration(const ModelInfo& model);

}  // namespace socc::sensors::velodyne
