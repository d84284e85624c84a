#pragma once
// Byte layout of Ouster lidar packets per UDP profile (Ouster's "Sensor Data" docs, firmware
// 2.x / 3.x): LEGACY (no packet header, 16 B column header, 4 B column status), and the
// profiles with a 32 B packet header, 12 B column headers and a 32 B packet footer.
#include <cstddef>
#include <cstdint>

#include "ouster_metadata.hpp"

namespace socc::sensors {

struct OusterLayout {
  OusterProfile profile = OusterProfile::kLegacy;
  std::size_t packet_header = 0, column_header = 0, channel = 0, column_footer = 0,
              packet_footer = 0;
  std::size_t column_size = 0, packet_size = 0;

  OusterLayout(OusterProfile profile, int pixels_per_column, int columns_per_packet);

  const std::uint8_t* column(const std::uint8_t* packet, int c) const {
    return packet + packet_header + static_cast<std::size_t>(c) * column_size;
  }
  const std::uint8_t* pixel(const std::uint8_t* column, int p) const {
    return column + column_header + static_cast<std::size_t>(p) * channel;
  }
  std::uint64_t timestamp(const std::uint8_t* column) const;  // [ns, sensor clock]
  std::uint16_t measurementId(const std::uint8_t* column) const;
  bool valid(const std::uint8_t* column) const;  // the column's status
  /// The packet's frame id (LEGACY: its first column's).
  std::uint16_t frameId(const std::uint8_t* packet) const;
};

struct OusterReturn {
  std::uint32_t range_mm = 0;  // 0: no return
  std::uint8_t reflectivity = 0;
};

/// The returns of one pixel: 1, or 2 for the dual profile (strongest first).
int ousterReturns(OusterProfile profile, const std::uint8_t* pixel, OusterReturn out[2]);

}  // namespace socc::sensors
