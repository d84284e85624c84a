#pragma once
// Synthetic Velodyne data packets for the tests, laid out as the user manuals describe them
// (12 blocks of flag, azimuth and 32 x (distance, reflectivity); time stamp; factory bytes).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "socc/sensors/packet.hpp"

namespace socc::sensors::test {

constexpr std::uint16_t kUpper = 0xEEFF, kLower = 0xDDFF, kBank3 = 0xCCFF, kBank4 = 0xBBFF;

struct Echo {
  std::uint16_t raw = 0;  // distance in the model's resolution; 0: no echo
  std::uint8_t reflectivity = 0;
};

struct BlockSpec {
  std::uint16_t flag = kUpper;
  std::uint16_t azimuth = 0;  // hundredths of a degree
  std::function<Echo(int channel)> echo;
};

inline void put16(std::vector<std::uint8_t>& d, std::size_t at, std::uint16_t v) {
  d[at] = static_cast<std::uint8_t>(v & 0xFF);
  d[at + 1] = static_cast<std::uint8_t>(v >> 8);
}

inline Packet velodynePacket(const std::vector<BlockSpec>& blocks, std::uint32_t stamp_us,
                             std::uint8_t mode, std::uint8_t product, std::int64_t arrival_ns) {
  Packet p;
  p.data.assign(1206, 0);
  for (std::size_t b = 0; b < blocks.size() && b < 12; ++b) {
    const std::size_t at = b * 100;
    put16(p.data, at, blocks[b].flag);
    put16(p.data, at + 2, blocks[b].azimuth);
    for (int c = 0; c < 32; ++c) {
      const Echo e = blocks[b].echo ? blocks[b].echo(c) : Echo{};
      put16(p.data, at + 4 + 3 * static_cast<std::size_t>(c), e.raw);
      p.data[at + 6 + 3 * static_cast<std::size_t>(c)] = e.reflectivity;
    }
  }
  for (int i = 0; i < 4; ++i)
    p.data[1200 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(stamp_us >> (8 * i));
  p.data[1204] = mode;
  p.data[1205] = product;
  p.stamp_ns = arrival_ns;
  p.source_ipv4 = 0xC0A801C9;  // 192.168.1.201
  p.source_port = 2368;
  p.destination_port = 2368;
  return p;
}

/// A calibration file (ROS velodyne YAML) with the given elevations [deg] and no other corrections.
inline std::filesystem::path writeYamlCalibration(const std::filesystem::path& file,
                                                  const std::vector<double>& vert_deg,
                                                  double resolution_m) {
  std::ofstream out(file);
  out << "lasers:\n";
  for (std::size_t i = 0; i < vert_deg.size(); ++i)
    out << "  - {laser_id: " << i
        << ", rot_correction: 0.0, vert_correction: " << vert_deg[i] * M_PI / 180.0
        << ", dist_correction: 0.0, vert_offset_correction: 0.0, horiz_offset_correction: 0.0}\n";
  out << "num_lasers: " << vert_deg.size() << "\ndistance_resolution: " << resolution_m << "\n";
  return file;
}

}  // namespace socc::sensors::test
