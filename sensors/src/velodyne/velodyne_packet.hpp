#pragma once
// Reading the fields of a Velodyne data packet (little-endian, velodyne_model.hpp offsets).
#include <cstdint>
#include <vector>

#include "velodyne_model.hpp"

namespace socc::sensors::velodyne {

inline std::uint16_t readU16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
inline std::uint32_t readU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

inline const std::uint8_t* blockAt(const std::vector<std::uint8_t>& data, int block) {
  return data.data() + static_cast<std::size_t>(block) * kBlockBytes;
}
inline std::uint16_t blockFlag(const std::vector<std::uint8_t>& data, int block) {
  return readU16(blockAt(data, block));
}
/// Hundredths of a degree (valid: 0..35999).
inline std::uint16_t blockAzimuth(const std::vector<std::uint8_t>& data, int block) {
  return readU16(blockAt(data, block) + 2);
}
inline std::uint32_t packetStamp(const std::vector<std::uint8_t>& data) {
  return readU32(data.data() + kStampOffset);
}

/// Azimuth advance from a to b in hundredths of a degree, 0..35999 (a full turn wraps).
inline int azimuthStep(int from, int to) {
  return ((to - from) % 36000 + 36000) % 36000;
}

}  // namespace socc::sensors::velodyne
