#pragma once
// Synthetic Ouster and Hesai packets and their configuration files, written from the vendors'
// packet documentation (not from the decoders): for the decoder tests of models and profiles the
// shared data has no recording of, and for the fuzzers' seed corpora (fuzz/fuzz_seeds.cpp).
// Header-only so that both can use it.
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace socc::sensors::test_packets {

inline void putLe(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i)
    b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

// ---- Ouster ------------------------------------------------------------------------------

struct OusterSpec {
  std::string profile = "RNG19_RFL8_SIG16_NIR16";  // or LEGACY, RNG15_RFL8_NIR8, ..._DUAL
  std::string prod_line = "OS-1-16";
  int beams = 16;
  int columns_per_frame = 512;  // lidar_mode 512x10
  int columns_per_packet = 16;
  std::uint32_t init_id = 4242;
  std::uint64_t serial = 992100000123;
  double beam_origin_mm = 15.806;
  std::uint64_t column_period_ns = 195312;  // 1 / (512 x 10 Hz)

  double altitude(int beam) const { return 15.0 - 30.0 * beam / beams; }  // [deg]
  double azimuth(int beam) const { return beam % 2 ? -1.5 : 1.5; }  // [deg]
  bool legacy() const { return profile == "LEGACY"; }
  bool dual() const { return profile == "RNG19_RFL8_SIG16_NIR16_DUAL"; }
  std::size_t channelSize() const {
    return legacy() ? 12 : profile == "RNG15_RFL8_NIR8" ? 4 : dual() ? 16 : 12;
  }
  std::size_t columnSize() const {
    return (legacy() ? 16 + 4 : 12) + static_cast<std::size_t>(beams) * channelSize();
  }
  std::size_t packetSize() const {
    return (legacy() ? 0 : 64) + static_cast<std::size_t>(columns_per_packet) * columnSize();
  }
};

struct OusterPixel {
  std::uint32_t range_mm = 0;  // 0: no return
  std::uint8_t reflectivity = 0;
  std::uint32_t range2_mm = 0;  // dual profile: the second strongest return
  std::uint8_t reflectivity2 = 0;
};

/// The metadata JSON of spec: flat (firmware 2.x) or nested (firmware 3.x) layout.
inline std::string ousterMetadata(const OusterSpec& s, bool nested = false) {
  std::ostringstream alt, az;
  for (int b = 0; b < s.beams; ++b) {
    alt << (b ? ", " : "") << s.altitude(b);
    az << (b ? ", " : "") << s.azimuth(b);
  }
  const std::string l2s = "[-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1]";
  const std::string mode = std::to_string(s.columns_per_frame) + "x10";
  std::ostringstream format;
  format << "{\"columns_per_frame\": " << s.columns_per_frame
         << ", \"columns_per_packet\": " << s.columns_per_packet << ", \"column_window\": [0, "
         << s.columns_per_frame - 1 << "], \"pixels_per_column\": " << s.beams
         << ", \"udp_profile_lidar\": \"" << s.profile << "\"}";
  std::ostringstream j;
  if (nested) {
    j << "{\"sensor_info\": {\"prod_line\": \"" << s.prod_line << "\", \"prod_sn\": \"" << s.serial
      << "\", \"initialization_id\": " << s.init_id << "},\n\"beam_intrinsics\": {"
      << "\"beam_altitude_angles\": [" << alt.str() << "], \"beam_azimuth_angles\": [" << az.str()
      << "], \"lidar_origin_to_beam_origin_mm\": " << s.beam_origin_mm
      << ", \"beam_to_lidar_transform\": [1, 0, 0, " << s.beam_origin_mm
      << ", 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]},\n\"lidar_intrinsics\": "
      << "{\"lidar_to_sensor_transform\": " << l2s << "},\n\"config_params\": {\"lidar_mode\": \""
      << mode << "\", \"udp_profile_lidar\": \"" << s.profile
      << "\"},\n\"lidar_data_format\": " << format.str() << "}\n";
  } else {
    j << "{\"prod_line\": \"" << s.prod_line << "\", \"prod_sn\": \"" << s.serial
      << "\", \"initialization_id\": " << s.init_id << ", \"lidar_mode\": \"" << mode
      << "\",\n\"beam_altitude_angles\": [" << alt.str() << "],\n\"beam_azimuth_angles\": ["
      << az.str() << "],\n\"lidar_origin_to_beam_origin_mm\": " << s.beam_origin_mm
      << ", \"lidar_to_sensor_transform\": " << l2s << ",\n\"data_format\": " << format.str()
      << "}\n";
  }
  return j.str();
}

/// One lidar packet of frame `frame` holding columns first_column... (measurement ids), the
/// column timestamps t0_ns + m * column_period_ns.
inline std::vector<std::uint8_t> ousterPacket(
    const OusterSpec& s, std::uint16_t frame, int first_column, std::uint64_t t0_ns,
    const std::function<OusterPixel(int column, int beam)>& pixel) {
  std::vector<std::uint8_t> b(s.packetSize(), 0);
  std::size_t at = 0;
  if (!s.legacy()) {  // packet header: type 1, frame id, init id u24, serial u40
    putLe(b, 0, 1, 2);
    putLe(b, 2, frame, 2);
    putLe(b, 4, s.init_id, 3);
    putLe(b, 7, s.serial, 5);
    at = 32;
  }
  for (int c = 0; c < s.columns_per_packet; ++c, at += s.columnSize()) {
    const int m = first_column + c;
    putLe(b, at, t0_ns + static_cast<std::uint64_t>(m) * s.column_period_ns, 8);
    putLe(b, at + 8, static_cast<std::uint64_t>(m), 2);
    if (s.legacy()) {
      putLe(b, at + 10, frame, 2);
      putLe(b, at + 12, static_cast<std::uint64_t>(m) * 90112 / s.columns_per_frame, 4);
      putLe(b, at + s.columnSize() - 4, 0xffffffffu, 4);
    } else {
      putLe(b, at + 10, 0x1, 2);  // status: valid
    }
    for (int beam = 0; beam < s.beams; ++beam) {
      const OusterPixel p = pixel(m, beam);
      const std::size_t px =
          at + (s.legacy() ? 16 : 12) + static_cast<std::size_t>(beam) * s.channelSize();
      if (s.legacy()) {
        putLe(b, px, p.range_mm & 0xfffff, 4);
        putLe(b, px + 4, p.reflectivity, 2);
        putLe(b, px + 6, 100, 2);  // signal
      } else if (s.profile == "RNG15_RFL8_NIR8") {
        putLe(b, px, (p.range_mm / 8) & 0x7fff, 2);
        b[px + 2] = p.reflectivity;
        b[px + 3] = 7;  // near infrared
      } else if (s.dual()) {
        putLe(b, px, (p.range_mm & 0x7ffff) | (std::uint64_t{p.reflectivity} << 24), 4);
        putLe(b, px + 4, (p.range2_mm & 0x7ffff) | (std::uint64_t{p.reflectivity2} << 24), 4);
        putLe(b, px + 8, 100, 2);
      } else {
        putLe(b, px, p.range_mm & 0x7ffff, 4);
        b[px + 4] = p.reflectivity;
        putLe(b, px + 6, 100, 2);
      }
    }
  }
  return b;
}

// ---- Hesai -------------------------------------------------------------------------------

struct HesaiSpec {
  std::string model = "pandarxt32";  // pandar40p, pandar64
  std::uint8_t return_mode = 0x37;   // strongest; 0x38 last; 0x39 last + strongest ...
  std::uint16_t motor_rpm = 600;
  int lasers() const { return model == "pandarxt32" ? 32 : model == "pandar40p" ? 40 : 64; }
  int blocks() const { return model == "pandarxt32" ? 8 : model == "pandar40p" ? 10 : 6; }
  int returns() const { return return_mode >= 0x39 ? 2 : 1; }
  double roundPeriodUs() const { return model == "pandarxt32" ? 50.0 : 55.56; }
  // Azimuth step between firing rounds [0.01 deg] at motor_rpm.
  int azimuthStep() const {
    return static_cast<int>(motor_rpm / 60.0 * 36000.0 * roundPeriodUs() * 1e-6 + 0.5);
  }
};

struct HesaiUnit {
  std::uint16_t distance = 0;  // [4 mm]
  std::uint8_t reflectivity = 0;
};

/// One packet whose first round is at azimuth (0.01 deg), its time the whole seconds `utc_s`
/// (written as the tail's date) plus `us` microseconds.
inline std::vector<std::uint8_t> hesaiPacket(
    const HesaiSpec& s, int azimuth, std::int64_t utc_s, std::uint32_t us,
    const std::function<HesaiUnit(int block, int laser)>& unit, std::uint32_t sequence = 0) {
  const bool xt = s.model == "pandarxt32", p40 = s.model == "pandar40p";
  const std::size_t header = xt ? 12 : p40 ? 0 : 8;
  const std::size_t unit_size = xt ? 4 : 3;
  const std::size_t block_size = (p40 ? 4 : 2) + s.lasers() * unit_size;
  const std::size_t tail = header + s.blocks() * block_size;
  std::vector<std::uint8_t> b(tail + (xt ? 28 : 22), 0);
  b[0] = 0xEE;
  b[1] = 0xFF;
  if (xt) {  // pre-header: protocol 6.1; header: lasers, blocks, -, 4 mm, returns, UDP seq on
    b[2] = 6;
    b[3] = 1;
    b[6] = 32;
    b[7] = 8;
    b[9] = 4;
    b[10] = static_cast<std::uint8_t>(s.returns());
    b[11] = 1;
  } else if (!p40) {  // Pandar64: lasers, blocks, -, 4 mm
    b[2] = 64;
    b[3] = 6;
    b[5] = 4;
  }
  for (int k = 0; k < s.blocks(); ++k) {
    const std::size_t at = header + k * block_size;
    const int round = k / s.returns();
    if (p40) {
      b[at] = 0xEE;
      b[at + 1] = 0xFF;
    }
    putLe(b, at + (p40 ? 2 : 0),
          static_cast<std::uint64_t>((azimuth + round * s.azimuthStep()) % 36000), 2);
    for (int l = 0; l < s.lasers(); ++l) {
      const HesaiUnit u = unit(k, l);
      const std::size_t ua = at + (p40 ? 4 : 2) + l * unit_size;
      putLe(b, ua, u.distance, 2);
      b[ua + 2] = u.reflectivity;
    }
  }
  // Date from utc_s (UTC), as year - base, month, day, hour, minute, second.
  const std::int64_t days = utc_s / 86400, secs = utc_s % 86400;
  // civil_from_days (Howard Hinnant's public-domain algorithm, re-derived here).
  const std::int64_t z = days + 719468, era = z / 146097, doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100), mp = (5 * doy + 2) / 153;
  const std::int64_t day = doy - (153 * mp + 2) / 5 + 1, month = mp < 10 ? mp + 3 : mp - 9;
  const std::int64_t year = yoe + era * 400 + (month <= 2 ? 1 : 0);
  const std::uint8_t date[6] = {static_cast<std::uint8_t>(year - (xt ? 1900 : 2000)),
                                static_cast<std::uint8_t>(month),
                                static_cast<std::uint8_t>(day),
                                static_cast<std::uint8_t>(secs / 3600),
                                static_cast<std::uint8_t>(secs / 60 % 60),
                                static_cast<std::uint8_t>(secs % 60)};
  if (xt) {  // reserved 10, return mode, motor speed, date, timestamp, factory, UDP sequence
    b[tail + 10] = s.return_mode;
    putLe(b, tail + 11, s.motor_rpm, 2);
    std::copy(date, date + 6, b.begin() + static_cast<long>(tail + 13));
    putLe(b, tail + 19, us, 4);
    b[tail + 23] = 0x42;
    putLe(b, tail + 24, sequence, 4);
  } else {  // reserved 5, temperature flag, reserved 2, motor speed, timestamp, return mode,
            // factory, date
    putLe(b, tail + 8, s.motor_rpm, 2);
    putLe(b, tail + 10, us, 4);
    b[tail + 14] = s.return_mode;
    b[tail + 15] = 0x42;
    std::copy(date, date + 6, b.begin() + static_cast<long>(tail + 16));
  }
  return b;
}

/// An angle-correction CSV: elevation 15 - 0.75 (n - 1) deg, azimuth offset +-(n % 4) * 0.5 deg.
inline double hesaiElevation(int laser) {
  return 15.0 - 0.75 * laser;
}
inline double hesaiAzimuthOffset(int laser) {
  return (laser % 2 ? -1 : 1) * (laser % 4) * 0.5;
}
inline std::string hesaiCalibrationCsv(int lasers) {
  std::ostringstream csv;
  csv << "Laser id,Elevation,Azimuth\n";
  for (int l = 0; l < lasers; ++l)
    csv << l + 1 << "," << hesaiElevation(l) << "," << hesaiAzimuthOffset(l) << "\n";
  return csv.str();
}

}  // namespace socc::sensors::test_packets
