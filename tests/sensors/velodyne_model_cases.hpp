#pragma once
// Velodyne models as their user manuals describe them (layout, firing timing, beam angles),
// written out independently of sensors/src/velodyne/velodyne_model.cpp, and streams of
// synthetic packets of a 10 Hz rotation. A point's distance encodes its block and channel
// (rawOf), its reflectivity the packet's index.
#include <array>
#include <cmath>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "velodyne_packets.hpp"

namespace socc::sensors::test {

inline constexpr double kHundredthsPerUs = 0.36;  // 10 turns a second

struct ModelCase {
  std::string model;
  double resolution;                             // [m]
  double period_us;                              // between packets
  std::uint8_t mode = 0x37, product = 0;         // factory bytes
  std::function<std::uint16_t(int block)> flag;  // expected block flags
  std::function<double(int block)> block_start;  // sequence start relative to the stamp [us]
  std::function<double(int block, int channel)> offset;  // firing time relative to the stamp [us]
  std::function<int(int block, int channel)> laser;
  std::vector<double> vert_deg;  // elevation per laser
  std::vector<double> rot_deg;   // azimuth offset per laser (empty: none)
  bool needs_calibration = false;
  int blocks = 12;
};

inline void PrintTo(const ModelCase& m, std::ostream* os) {
  *os << m.model << (m.mode == 0x39 ? " dual" : "");
}

inline std::uint16_t rawOf(int block, int channel) {
  return static_cast<std::uint16_t>(1500 + 32 * block + channel);
}

inline std::vector<double> spread(int n, double lo, double hi) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(lo + (hi - lo) * i / (n - 1));
  return v;
}

// The manuals' facts, written out independently of sensors/src/velodyne/velodyne_model.cpp.
inline ModelCase hdl32e() {
  ModelCase m;
  m.model = "hdl32e";
  m.resolution = 0.002;
  m.period_us = 12 * 46.08;
  m.product = 0x21;
  m.flag = [](int) { return kUpper; };
  m.block_start = [](int b) { return 46.08 * b; };
  m.offset = [](int b, int c) { return 46.08 * b + 1.152 * c; };  // HDL-32E: 1.152 us per firing
  m.laser = [](int, int c) { return c; };
  m.vert_deg = {-30.67, -9.33, -29.33, -8.00, -28.00, -6.67, -26.67, -5.33,
                -25.33, -4.00, -24.00, -2.67, -22.67, -1.33, -21.33, 0.00,
                -20.00, 1.33,  -18.67, 2.67,  -17.33, 4.00,  -16.00, 5.33,
                -14.67, 6.67,  -13.33, 8.00,  -12.00, 9.33,  -10.67, 10.67};
  return m;
}

inline ModelCase vlp32c() {
  ModelCase m;
  m.model = "vlp32c";
  m.resolution = 0.004;
  m.period_us = 12 * 55.296;
  m.product = 0x28;
  m.flag = [](int) { return kUpper; };
  m.block_start = [](int b) { return 55.296 * b; };
  m.offset = [](int b, int c) { return 55.296 * b + 2.304 * (c / 2); };  // lasers fire in pairs
  m.laser = [](int, int c) { return c; };
  m.vert_deg = {-25,    -1,    -1.667, -15.639, -11.31, 0,     -0.667, -8.843,
                -7.254, 0.333, -0.333, -6.148,  -5.333, 1.333, 0.667,  -4,
                -4.667, 1.667, 1,      -3.667,  -3.333, 3.333, 2.333,  -2.667,
                -3,     7,     4.667,  -2.333,  -2,     15,    10.333, -1.333};
  // VLP-32C manual: the beams' azimuth offsets (ROS sign: the beam points at azimuth - offset).
  m.rot_deg = {-1.4, 4.2,  -1.4, 1.4,  -1.4, 1.4,  -4.2, 1.4,  -1.4, 4.2,  -1.4,
               1.4,  -4.2, 1.4,  -4.2, 1.4,  -1.4, 4.2,  -1.4, 4.2,  -4.2, 1.4,
               -1.4, 1.4,  -1.4, 1.4,  -1.4, 4.2,  -4.2, 1.4,  -1.4, 1.4};
  return m;
}

inline ModelCase vlp16(bool dual) {
  ModelCase m;
  m.model = "vlp16";
  m.resolution = 0.002;
  m.period_us = (dual ? 12 : 24) * 55.296;
  m.product = 0x22;
  m.mode = dual ? 0x39 : 0x37;
  m.flag = [](int) { return kUpper; };
  // Dual: blocks 2k and 2k+1 hold the same two sequences (last / strongest returns).
  m.block_start = [dual](int b) { return 55.296 * (dual ? 2 * (b / 2) : 2 * b); };
  m.offset = [dual](int b, int c) {
    return 55.296 * ((dual ? 2 * (b / 2) : 2 * b) + c / 16) + 2.304 * (c % 16);
  };
  m.laser = [](int, int c) { return c % 16; };
  m.vert_deg = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
  return m;
}

// HDL-64E, as the firing time tables reproduced by VeloView, Apollo's driver and
// velodyne_decoder give it (docs/sensors.md, "HDL-64E"): upper block (FF EE, lasers 0-31) and
// lower block (FF DD, 32-63) fire together, laser c in group c / 4. Single return (S2, S3):
// firing k = block / 2 of 6, 48 us each, groups 6 us apart, the lasers of a group at 0, 1.26,
// 2.46, 3.66 us; laser 0 of the first firing 288 us before the stamp. S3 dual return: firing
// k = block / 4 of 3 (upper / lower strongest, then upper / lower last), 57.6 us each, groups
// 7.2 us apart at 0, 1.3, 2.5, 3.7 us; the S3 table's first entry: 172.8 us before the stamp.
inline ModelCase hdl64e(bool dual) {
  ModelCase m;
  m.model = "hdl64e";
  m.resolution = 0.002;
  m.mode = dual ? 0x39 : 0x37;  // the HDL-64E has no return-mode byte: status bytes, unread
  m.period_us = dual ? 3 * 57.6 : 6 * 48.0;
  m.flag = [](int b) { return b % 2 == 0 ? kUpper : kLower; };
  const double cycle = dual ? 57.6 : 48.0;
  const int per_firing = dual ? 4 : 2;
  const double first = dual ? 172.8 : 288.0;
  const double group = dual ? 7.2 : 6.0;
  const std::array<double, 4> in_group = dual ? std::array<double, 4>{0.0, 1.3, 2.5, 3.7}
                                              : std::array<double, 4>{0.0, 1.26, 2.46, 3.66};
  m.block_start = [=](int b) { return -first + cycle * (b / per_firing); };
  m.offset = [=](int b, int c) {
    return -first + cycle * (b / per_firing) + group * (c / 4) +
           in_group[static_cast<std::size_t>(c % 4)];
  };
  m.laser = [](int b, int c) { return c + 32 * (b % 2); };
  m.vert_deg = spread(64, -24.8, 2.0);
  m.needs_calibration = true;
  return m;
}

// VLS-128: blocks of banks FF EE / DD / CC / BB (lasers 0-31 ... 96-127), three sequences a
// packet; group = laser / 8 + laser / 64, 2.665 us a group, 53.3 us a sequence, the stamp
// 8.7 us after the sequence start.
inline ModelCase vls128(bool dual) {
  ModelCase m;
  m.model = "vls128";
  m.resolution = 0.004;
  m.period_us = dual ? 53.3 : 3 * 53.3;
  m.product = 0x63;
  m.mode = dual ? 0x39 : 0x37;
  const auto bank = [dual](int b) { return dual ? b / 2 : b % 4; };
  const auto seq = [dual](int b) { return dual ? 0 : b / 4; };
  m.flag = [bank](int b) {
    const std::uint16_t f[4] = {kUpper, kLower, kBank3, kBank4};
    return f[bank(b)];
  };
  m.block_start = [seq](int b) { return 53.3 * seq(b) - 8.7; };
  m.laser = [bank](int b, int c) { return 32 * bank(b) + c; };
  m.offset = [seq, bank](int b, int c) {
    const int laser = 32 * bank(b) + c;
    return 53.3 * seq(b) + 2.665 * (laser / 8 + laser / 64) - 8.7;
  };
  m.vert_deg = spread(128, -25.0, 15.0);
  m.needs_calibration = true;
  m.blocks = dual ? 8 : 12;
  return m;
}

inline std::vector<Packet> makePackets(const ModelCase& m, int count,
                                       std::uint32_t first_stamp_us) {
  std::vector<Packet> packets;
  for (int k = 0; k < count; ++k) {
    const double stamp = first_stamp_us + k * m.period_us;
    std::vector<BlockSpec> blocks;
    for (int b = 0; b < m.blocks; ++b) {
      const double az = std::fmod(kHundredthsPerUs * (stamp + m.block_start(b)), 36000.0);
      blocks.push_back(
          {m.flag(b), static_cast<std::uint16_t>(std::lround(az) % 36000), [b, k](int c) {
             return Echo{rawOf(b, c), static_cast<std::uint8_t>(k)};
           }});
    }
    packets.push_back(
        velodynePacket(blocks, static_cast<std::uint32_t>(std::lround(stamp)), m.mode, m.product,
                       static_cast<std::int64_t>(std::llround(stamp * 1000.0)) + 2'000'000));
  }
  return packets;
}

}  // namespace socc::sensors::test
