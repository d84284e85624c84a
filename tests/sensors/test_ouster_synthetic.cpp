// Ouster profiles the shared data has no recording of (LEGACY, RNG19_RFL8_SIG16_NIR16, dual),
// and bad input, on packets built from Ouster's packet documentation (vendor_packets.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "../temp_dir.hpp"
#include "socc/sensors/ouster_decoder.hpp"
#include "vendor_packets.hpp"

namespace socc::sensors {
namespace {

using test_packets::OusterPixel;
using test_packets::OusterSpec;

constexpr std::uint64_t kT0 = 1'000'000'000'000;  // sensor time of frame 0, column 0 [ns]
constexpr std::uint64_t kFramePeriod = 100'000'000;

// Every third pixel has no return; ranges are multiples of 8 mm (the low-bandwidth unit).
OusterPixel syntheticPixel(int column, int beam) {
  OusterPixel p;
  if ((column + beam) % 3 == 0) return p;
  p.range_mm = 8u * static_cast<std::uint32_t>(300 + 7 * beam + column % 50);
  p.reflectivity = static_cast<std::uint8_t>(column + beam);
  if (beam % 4 == 0) {
    p.range2_mm = p.range_mm + 4000;
    p.reflectivity2 = 3;
  }
  return p;
}

// The packets of frames first_frame .. first_frame + frames - 1.
std::vector<Packet> ousterFrames(const OusterSpec& s, int first_frame, int frames) {
  std::vector<Packet> packets;
  for (int f = first_frame; f < first_frame + frames; ++f)
    for (int c = 0; c < s.columns_per_frame; c += s.columns_per_packet) {
      Packet p;
      p.data = test_packets::ousterPacket(s, static_cast<std::uint16_t>(f), c,
                                          kT0 + static_cast<std::uint64_t>(f) * kFramePeriod,
                                          syntheticPixel);
      packets.push_back(std::move(p));
    }
  return packets;
}

// Ouster's range-to-XYZ formula (sensor docs, "Lidar Range to XYZ"), then the
// lidar-to-sensor transform of the metadata (180 deg about z, +36.18 mm in z).
Eigen::Vector3d expectedOusterPoint(const OusterSpec& s, int column, int beam, double range_mm) {
  const double enc = 2 * M_PI * (1.0 - static_cast<double>(column) / s.columns_per_frame);
  const double az = -2 * M_PI * s.azimuth(beam) / 360, alt = 2 * M_PI * s.altitude(beam) / 360;
  const double n = s.beam_origin_mm;
  const Eigen::Vector3d lidar(
      (range_mm - n) * std::cos(enc + az) * std::cos(alt) + n * std::cos(enc),
      (range_mm - n) * std::sin(enc + az) * std::cos(alt) + n * std::sin(enc),
      (range_mm - n) * std::sin(alt));
  return Eigen::Vector3d(-lidar.x(), -lidar.y(), lidar.z() + 36.18) * 1e-3;
}

struct OusterDecoded {
  std::vector<SensorScan> scans;
  DecodeStats stats;
};

OusterDecoded decodeOuster(const SensorConfig& config, const std::vector<Packet>& packets) {
  auto decoder = makeOusterDecoder(config);
  OusterDecoded d;
  for (const Packet& p : packets) decoder->feed(p, d.scans);
  decoder->flush(d.scans);
  d.stats = decoder->stats();
  return d;
}

class OusterProfiles : public ::testing::TestWithParam<std::string> {
 protected:
  socc::testing::TempDir dir;
};

TEST_P(OusterProfiles, DecodeTheDocumentedGeometryTimesAndReturns) {
  OusterSpec s;
  s.profile = GetParam();
  SensorConfig config;
  config.model = "os1-16";
  config.calibration = dir.write("meta.json", test_packets::ousterMetadata(s, s.dual()));
  // Frame 7 starts mid-way (dropped), 8 and 9 complete, then the first packet of 10.
  std::vector<Packet> packets = ousterFrames(s, 7, 4);
  packets.erase(packets.begin(), packets.begin() + 10);
  packets.resize(packets.size() - 31);
  const OusterDecoded d = decodeOuster(config, packets);
  EXPECT_EQ(d.stats.packets, packets.size());
  EXPECT_EQ(d.stats.foreign + d.stats.malformed + d.stats.late + d.stats.gaps, 0u);
  ASSERT_EQ(d.scans.size(), 2u);

  const double period_s = s.column_period_ns * 1e-9;
  for (std::size_t k = 0; k < 2; ++k) {
    const SensorScan& scan = d.scans[k];
    EXPECT_TRUE(scan.complete);
    EXPECT_EQ(scan.stamp_ns, static_cast<std::int64_t>(kT0 + (8 + k) * kFramePeriod));
    std::size_t expected_points = 0;
    for (int m = 0; m < s.columns_per_frame; ++m)
      for (int b = 0; b < s.beams; ++b) {
        const OusterPixel p = syntheticPixel(m, b);
        expected_points += (p.range_mm ? 1 : 0) + (s.dual() && p.range2_mm ? 1 : 0);
      }
    ASSERT_EQ(scan.size(), expected_points);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      // The column from the point's time (column timestamps are m column periods apart).
      const int m = static_cast<int>(std::lround(scan.time[i] / period_s));
      const int b = scan.ring[i];
      const OusterPixel p = syntheticPixel(m, b);
      const bool second = scan.return_index[i] == 1;
      const double range = second ? p.range2_mm : p.range_mm;
      ASSERT_NEAR(scan.time[i], m * period_s, 1e-7);
      ASSERT_LT((scan.points[i].cast<double>() - expectedOusterPoint(s, m, b, range)).norm(), 1e-4)
          << "column " << m << " beam " << b;
      ASSERT_EQ(scan.intensity[i], second ? p.reflectivity2 : p.reflectivity);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Ouster, OusterProfiles,
                         ::testing::Values("LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG15_RFL8_NIR8",
                                           "RNG19_RFL8_SIG16_NIR16_DUAL"));

TEST(OusterDual, ReturnSelection) {
  socc::testing::TempDir dir;
  OusterSpec s;
  s.profile = "RNG19_RFL8_SIG16_NIR16_DUAL";
  SensorConfig config;
  config.calibration = dir.write("meta.json", test_packets::ousterMetadata(s));
  const auto packets = ousterFrames(s, 0, 1);
  std::map<ReturnMode, std::size_t> points;
  for (const ReturnMode mode :
       {ReturnMode::kAll, ReturnMode::kStrongest, ReturnMode::kFirst, ReturnMode::kLast}) {
    config.returns = mode;
    const OusterDecoded d = decodeOuster(config, packets);
    ASSERT_EQ(d.scans.size(), 1u);
    points[mode] = d.scans[0].size();
    if (mode == ReturnMode::kLast)  // the second return (farther) wherever there is one
      for (std::size_t i = 0; i < d.scans[0].size(); ++i)
        if (d.scans[0].ring[i] % 4 == 0) {
          ASSERT_EQ(d.scans[0].return_index[i], 1);
        }
  }
  EXPECT_GT(points[ReturnMode::kAll], points[ReturnMode::kStrongest]);
  EXPECT_EQ(points[ReturnMode::kStrongest], points[ReturnMode::kFirst]);
  EXPECT_EQ(points[ReturnMode::kStrongest], points[ReturnMode::kLast]);
}

class OusterBadInput : public ::testing::Test {
 protected:
  OusterBadInput() {
    config.model = "os1-16";
    config.calibration = dir.write("meta.json", test_packets::ousterMetadata(s));
  }
  socc::testing::TempDir dir;
  OusterSpec s;
  SensorConfig config;
};

TEST_F(OusterBadInput, LostPacketDropsOrFlagsTheFrame) {
  std::vector<Packet> packets = ousterFrames(s, 0, 3);
  packets.erase(packets.begin() + 32 + 5);  // a packet of frame 1
  OusterDecoded d = decodeOuster(config, packets);
  EXPECT_EQ(d.scans.size(), 2u);  // frames 0 and 2
  EXPECT_EQ(d.stats.gaps, 1u);
  config.keep_partial = true;
  d = decodeOuster(config, packets);
  ASSERT_EQ(d.scans.size(), 3u);
  EXPECT_FALSE(d.scans[1].complete);
  EXPECT_EQ(d.stats.partial_scans, 1u);
}

TEST_F(OusterBadInput, ReorderedAndLatePackets) {
  std::vector<Packet> packets = ousterFrames(s, 0, 2);
  std::swap(packets[3], packets[4]);    // within a frame: harmless
  std::swap(packets[31], packets[32]);  // frame 1 starts before frame 0's last packet
  OusterDecoded d = decodeOuster(config, packets);
  EXPECT_EQ(d.stats.late, 1u);    // frame 0's last packet, after frame 1 began
  ASSERT_EQ(d.scans.size(), 1u);  // frame 1; frame 0 lost its last packet
  EXPECT_EQ(d.stats.gaps, 0u);    // (the first frame: not counted as a gap)
  EXPECT_TRUE(d.scans[0].complete);
}

TEST_F(OusterBadInput, TruncatedForeignAndSecondSensorPacketsAreCountedDrops) {
  std::vector<Packet> packets = ousterFrames(s, 0, 1);
  Packet truncated = packets[2];
  truncated.data.resize(truncated.data.size() - 100);
  Packet imu;
  imu.data.assign(48, 0);
  OusterSpec other = s;
  other.serial = 123;
  Packet second_sensor;
  second_sensor.data = test_packets::ousterPacket(other, 0, 0, kT0, syntheticPixel);
  Packet bad_column = packets[5];
  bad_column.data[32 + 8] = 0xff;  // measurement id 0xffxx: beyond the frame
  bad_column.data[32 + 9] = 0xff;
  packets.insert(packets.begin() + 3, {truncated, imu, second_sensor, bad_column});
  const OusterDecoded d = decodeOuster(config, packets);
  EXPECT_EQ(d.stats.malformed, 2u);
  EXPECT_EQ(d.stats.foreign, 2u);
  ASSERT_EQ(d.scans.size(), 1u);
  EXPECT_TRUE(d.scans[0].complete);
}

TEST_F(OusterBadInput, PacketsOfAnotherFormatAreRefused) {
  OusterSpec bigger = s;
  bigger.beams = 64;
  bigger.prod_line = "OS-1-64";
  auto decoder = makeOusterDecoder(config);
  std::vector<SensorScan> scans;
  try {
    for (const Packet& p : ousterFrames(bigger, 0, 2)) decoder->feed(p, scans);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("do not fit the metadata"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(scans.empty());
}

TEST_F(OusterBadInput, WrongMetadataIsRefusedWithItsReason) {
  const auto message = [&](const std::string& model, const std::string& json) {
    SensorConfig c;
    c.model = model;
    c.calibration = dir.write("bad.json", json);
    try {
      makeOusterDecoder(c);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string good = test_packets::ousterMetadata(s);
  EXPECT_NE(message("os2-64", good).find("configured as os2-64"), std::string::npos);
  EXPECT_NE(message("os1-16", good.substr(0, good.size() / 2)).find("not a JSON"),
            std::string::npos);
  std::string no_angles = good;
  no_angles.replace(no_angles.find("beam_altitude_angles"), 20, "beam_altitude_anglez");
  EXPECT_NE(message("os1-16", no_angles).find("beam_altitude_angles"), std::string::npos);
  std::string few = good;
  few.replace(few.find("\"beam_azimuth_angles\": [") + 24, 5, "");
  EXPECT_NE(message("", few).find("beam_azimuth_angles"), std::string::npos);
  std::string mode = good;
  mode.replace(mode.find("512x10"), 6, "500x10");
  EXPECT_NE(message("", mode).find("lidar_mode"), std::string::npos);
  std::string beams = good;
  beams.replace(beams.find("OS-1-16"), 7, "OS-1-64");
  EXPECT_NE(message("", beams).find("disagree"), std::string::npos);
  SensorConfig none;
  none.model = "os1-16";
  EXPECT_THROW(makeOusterDecoder(none), std::runtime_error);
  none.calibration = dir.path() / "missing.json";
  EXPECT_THROW(makeOusterDecoder(none), std::runtime_error);
}

TEST(OusterModels, Names) {
  EXPECT_TRUE(isOusterModel("os0-128"));
  EXPECT_TRUE(isOusterModel("os2-32"));
  EXPECT_FALSE(isOusterModel("os3-64"));
  EXPECT_FALSE(isOusterModel("vlp16"));
}

}  // namespace
}  // namespace socc::sensors
