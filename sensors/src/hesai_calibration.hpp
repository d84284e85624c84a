#pragma once
// A Hesai angle-correction CSV (PandarView / the sensor's own export): a header line, then one
// line per channel "id,elevation,azimuth" [deg], ids 1..N.
#include <filesystem>
#include <vector>

namespace socc::sensors {

struct HesaiCalibration {
  std::vector<float> elevation_deg;       // per channel, channel 1 first
  std::vector<float> azimuth_offset_deg;  // added to the block azimuth
};

/// Reads file, which must hold exactly `lasers` channels; throws std::runtime_error naming the
/// file, the line and the problem otherwise (another model's file, damaged values).
HesaiCalibration readHesaiCalibration(const std::filesystem::path& file, int lasers);

}  // namespace socc::sensors
