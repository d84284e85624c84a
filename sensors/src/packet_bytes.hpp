#pragma once
// Little-endian fields of LiDAR packets (Ouster, Hesai: all little-endian), read byte by byte so
// that any alignment and any host order work. Callers check the packet's size first.
#include <cstddef>
#include <cstdint>

namespace socc::sensors::packet_bytes {

inline std::uint16_t u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

inline std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

inline std::uint64_t u64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(u32(p)) | (static_cast<std::uint64_t>(u32(p + 4)) << 32);
}

}  // namespace socc::sensors::packet_bytes
