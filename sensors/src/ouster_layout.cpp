#include "ouster_layout.hpp"

#include "packet_bytes.hpp"

namespace socc::sensors {

using packet_bytes::u16;
using packet_bytes::u32;
using packet_bytes::u64;

OusterLayout::OusterLayout(OusterProfile p, int pixels_per_column, int columns_per_packet)
    : profile(p) {
  const bool legacy = p == OusterProfile::kLegacy;
  packet_header = legacy ? 0 : 32;
  column_header = legacy ? 16 : 12;
  column_footer = legacy ? 4 : 0;
  packet_footer = legacy ? 0 : 32;
  switch (p) {
    case OusterProfile::kLegacy:
      channel = 12;
      break;
    case OusterProfile::kSingle:
      channel = 12;
      break;
    case OusterProfile::kLowData:
      channel = 4;
      break;
    case OusterProfile::kDual:
      channel = 16;
      break;
  }
  column_size =
      column_header + static_cast<std::size_t>(pixels_per_column) * channel + column_footer;
  packet_size =
      packet_header + static_cast<std::size_t>(columns_per_packet) * column_size + packet_footer;
}

// Column header: timestamp u64, measurement id u16, then status u16 (profiles) or frame id
// u16 + encoder count u32 (LEGACY, whose status u32 follows the pixels).
std::uint64_t OusterLayout::timestamp(const std::uint8_t* column) const {
  return u64(column);
}

std::uint16_t OusterLayout::measurementId(const std::uint8_t* column) const {
  return u16(column + 8);
}

// Bit 0 of the status: the column holds data (LEGACY: all ones when valid, as the SDK reads it).
bool OusterLayout::valid(const std::uint8_t* column) const {
  if (profile == OusterProfile::kLegacy) return (u32(column + column_size - 4) & 0x1) != 0;
  return (u16(column + 10) & 0x1) != 0;
}

// Packet header (profiles): packet type u16, frame id u16, init id u24, serial u40, ...
std::uint16_t OusterLayout::frameId(const std::uint8_t* packet) const {
  if (profile == OusterProfile::kLegacy) return u16(column(packet, 0) + 10);
  return u16(packet + 2);
}

int ousterReturns(OusterProfile profile, const std::uint8_t* px, OusterReturn out[2]) {
  switch (profile) {
    case OusterProfile::kLegacy:  // range 20 bits [mm], reflectivity u16 (saturated to 255)
      out[0].range_mm = u32(px) & 0xfffffu;
      out[0].reflectivity = static_cast<std::uint8_t>(u16(px + 4) > 255 ? 255 : u16(px + 4));
      return 1;
    case OusterProfile::kSingle:  // range 19 bits [mm], reflectivity u8 at byte 4
      out[0].range_mm = u32(px) & 0x7ffffu;
      out[0].reflectivity = px[4];
      return 1;
    case OusterProfile::kLowData:  // range 15 bits [8 mm], reflectivity u8 at byte 2
      out[0].range_mm = (u16(px) & 0x7fffu) * 8u;
      out[0].reflectivity = px[2];
      return 1;
    case OusterProfile::kDual:  // two words: range 19 bits + reflectivity in the top byte
      out[0].range_mm = u32(px) & 0x7ffffu;
      out[0].reflectivity = px[3];
      out[1].range_mm = u32(px + 4) & 0x7ffffu;
      out[1].reflectivity = px[7];
      return 2;
  }
  return 0;
}

}  // namespace socc::sensors
