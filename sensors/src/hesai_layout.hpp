#pragma once
// Packet layouts and firing timing of the supported Hesai models, from their user manuals
// (docs/sensors_ouster_hesai.md): PandarXT32 (protocol 6.1), Pandar40P and Pandar64. One
// parsed, validated packet is a HesaiPacket; the decoder (hesai_decoder.cpp) builds sweeps.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace socc::sensors {

struct HesaiLayout {
  std::string model;  // pandarxt32, pandar40p, pandar64
  int lasers = 0;
  int blocks = 0;
  std::size_t header_size = 0;  // before the first block
  bool block_flag = false;      // every block starts with EE FF (Pandar40P: no packet header)
  std::size_t unit_size = 0;    // distance u16, reflectivity u8 (+ 1 reserved on the XT32)
  std::size_t size = 0;         // payload without the optional UDP sequence number
  bool has_sequence = false;    // + 4 bytes UDP sequence; the XT32 always sends it
  // Tail fields, offsets from the start of the tail (= header + body).
  std::size_t tail_return_mode = 0, tail_motor_speed = 0, tail_date = 0, tail_timestamp = 0;
  int year_base = 1900;    // the date's year byte counts from this year
  double min_range = 0.0;  // [m] the model's shortest / longest range (manual)
  double max_range = 0.0;
  double firing_period_us = 0.0;  // between two firing rounds (blocks of one return)
  // Point time relative to the packet's timestamp t0 [ns]: last_round_ns for the last round of
  // the packet, minus firing_period_us for each round before it, plus channel_ns[channel].
  std::int64_t last_round_ns = 0;
  std::vector<std::int64_t> channel_ns;
  std::vector<float> nominal_elevation_deg;  // when the model has nominal angles (else empty)

  std::size_t blockSize() const { return (block_flag ? 4 : 2) + lasers * unit_size; }
  std::size_t tailOffset() const { return header_size + blocks * blockSize(); }
  std::int64_t pointOffsetNs(int block, int channel, int returns) const;
};

/// The layout of a supported model, or nullptr.
const HesaiLayout* hesaiLayout(const std::string& model);
/// Every supported layout, in a fixed order.
const std::vector<HesaiLayout>& hesaiLayouts();

enum class HesaiReturns : std::uint8_t { kSingle, kDual };

struct HesaiPacket {
  std::int64_t time_ns = 0;  // t0: the date and the microseconds of the tail [ns since 1970]
  std::uint8_t return_mode = 0;
  int returns = 1;  // 1 or 2 blocks per firing round
  double distance_unit_m = 0.004;
  std::uint16_t motor_rpm = 0;
  bool has_sequence = false;
  std::uint32_t sequence = 0;
};

enum class HesaiCheck { kOk, kForeign, kMalformed };

/// Validates payload as a packet of layout (size, header counts, block flags, return mode
/// against the header's return number, azimuths, date, azimuth step against motor speed and
/// firing period) and fills packet; why says what is wrong otherwise.
HesaiCheck parseHesaiPacket(const HesaiLayout& layout, const std::uint8_t* data, std::size_t size,
                            HesaiPacket& packet, std::string& why);

/// The supported model whose layout payload matches exactly (size and header counts), or "".
std::string detectHesaiModel(const std::uint8_t* data, std::size_t size);

/// Block azimuth [0.01 deg] of block b.
std::uint16_t hesaiBlockAzimuth(const HesaiLayout& layout, const std::uint8_t* data, int block);
/// Pointer to the unit (distance, reflectivity) of channel c in block b.
const std::uint8_t* hesaiUnit(const HesaiLayout& layout, const std::uint8_t* data, int block,
                              int channel);

}  // namespace socc::sensors
