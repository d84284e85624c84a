#pragma once
// An Ouster sensor's metadata JSON (what the sensor's HTTP API and the SDK save next to a
// recording): beam angles, lidar-to-sensor transform, data format. Both the flat layout of
// firmware 2.x and the nested layout of firmware 2.4+ / 3.x are read.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace socc::sensors {

enum class OusterProfile { kLegacy, kSingle, kLowData, kDual };

struct OusterMetadata {
  std::string model;          // "os1-128", from prod_line
  std::string prod_line;      // as written, e.g. "OS-1-128"
  std::uint64_t serial = 0;   // prod_sn; 0: unknown
  std::uint32_t init_id = 0;  // initialization_id; 0: unknown
  OusterProfile profile = OusterProfile::kLegacy;
  std::string profile_name;   // e.g. "RNG15_RFL8_NIR8"
  int pixels_per_column = 0;  // beams
  int columns_per_frame = 0;
  int columns_per_packet = 16;
  int window_first = 0, window_last = 0;  // column_window, inclusive (may wrap)
  double frequency_hz = 10.0;
  std::vector<double> beam_altitude_deg, beam_azimuth_deg;
  std::array<double, 16> beam_to_lidar{};    // row-major; translation [mm]
  std::array<double, 16> lidar_to_sensor{};  // row-major; translation [mm]

  int windowColumns() const;
  bool inWindow(int column) const;
};

/// Reads and checks file; throws std::runtime_error naming the file and the field otherwise.
OusterMetadata readOusterMetadata(const std::filesystem::path& file);

/// "OS-1-128" -> "os1-128"; "" when it is not an OS0/OS1/OS2 product line.
std::string ousterModelName(const std::string& prod_line);

}  // namespace socc::sensors
