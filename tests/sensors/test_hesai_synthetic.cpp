// Hesai models and modes the shared data has no recording of (Pandar40P, Pandar64, single and
// dual returns, scan cut), and bad input, on packets built from the user manuals' layouts and
// firing-time tables (vendor_packets.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "../temp_dir.hpp"
#include "socc/sensors/hesai_decoder.hpp"
#include "vendor_packets.hpp"

namespace socc::sensors {
namespace {

using test_packets::HesaiSpec;
using test_packets::HesaiUnit;

constexpr std::int64_t kUtc = 1'700'000'000;  // 2023-11-14 22:13:20 UTC

// Every unit has a return, distance 10 m + 4 mm * laser, reflectivity = laser + block.
HesaiUnit everyUnit(int block, int laser) {
  return {static_cast<std::uint16_t>(2500 + laser), static_cast<std::uint8_t>(laser + block)};
}

struct HesaiStream {
  std::vector<Packet> packets;
  std::vector<int> azimuth;        // first round of each packet [0.01 deg]
  std::vector<std::int64_t> time;  // t0 of each packet [ns]
};

// count packets from azimuth start, one round per firing period of the model.
HesaiStream hesaiStream(const HesaiSpec& s, int start, int count,
                        const std::function<HesaiUnit(int, int)>& unit = everyUnit) {
  HesaiStream st;
  const int rounds = s.blocks() / s.returns();
  const auto packet_us = static_cast<std::int64_t>(std::lround(rounds * s.roundPeriodUs()));
  for (int k = 0; k < count; ++k) {
    const int az = (start + k * rounds * s.azimuthStep()) % 36000;
    const std::int64_t us = 500'000 + k * packet_us;
    Packet p;
    p.data = test_packets::hesaiPacket(s, az, kUtc + us / 1'000'000,
                                       static_cast<std::uint32_t>(us % 1'000'000), unit,
                                       static_cast<std::uint32_t>(k));
    st.packets.push_back(std::move(p));
    st.azimuth.push_back(az);
    st.time.push_back(kUtc * 1'000'000'000 + us * 1000);
  }
  return st;
}

struct HesaiDecoded {
  std::vector<SensorScan> scans;
  DecodeStats stats;
};

HesaiDecoded decodeHesai(const SensorConfig& config, const std::vector<Packet>& packets) {
  auto decoder = makeHesaiDecoder(config);
  HesaiDecoded d;
  for (const Packet& p : packets) decoder->feed(p, d.scans);
  decoder->flush(d.scans);
  d.stats = decoder->stats();
  return d;
}

// Hesai's angles (manual: azimuth clockwise from the front) with the CSV's corrections, in
// socc's frame (x forward, y left).
Eigen::Vector3d expectedHesaiPoint(int block_azimuth, int laser, double distance_m) {
  const double az = (block_azimuth / 100.0 + test_packets::hesaiAzimuthOffset(laser)) * M_PI / 180;
  const double el = test_packets::hesaiElevation(laser) * M_PI / 180;
  return {distance_m * std::cos(el) * std::cos(az), -distance_m * std::cos(el) * std::sin(az),
          distance_m * std::sin(el)};
}

class HesaiModels : public ::testing::TestWithParam<std::string> {
 protected:
  socc::testing::TempDir dir;
};

// One complete rotation between two cuts at 0 deg: every point where the manual puts it, at the
// time its firing-time table gives.
TEST_P(HesaiModels, SingleReturnGeometryAndFiringTimes) {
  HesaiSpec s;
  s.model = GetParam();
  SensorConfig config;
  config.model = s.model;
  config.calibration = dir.write("angles.csv", test_packets::hesaiCalibrationCsv(s.lasers()));
  const int per_packet = s.blocks() * s.azimuthStep();  // [0.01 deg]
  const int packets_per_rotation = 36000 / per_packet;
  // 2.5 rotations from about 100 deg: one complete rotation between the cuts, starting with a
  // packet whose first round is at 0 deg.
  const HesaiStream st = hesaiStream(s, per_packet * 70, packets_per_rotation * 5 / 2);
  const HesaiDecoded d = decodeHesai(config, st.packets);
  EXPECT_EQ(d.stats.packets, st.packets.size());
  EXPECT_EQ(d.stats.foreign + d.stats.malformed + d.stats.late + d.stats.gaps, 0u);
  ASSERT_EQ(d.scans.size(), 1u);
  const SensorScan& scan = d.scans[0];
  EXPECT_TRUE(scan.complete);
  ASSERT_EQ(scan.size(), static_cast<std::size_t>(packets_per_rotation * s.blocks() * s.lasers()));

  // The rotation's first packet: the one whose first round is at 0 deg.
  const auto first = static_cast<std::size_t>(std::find(st.azimuth.begin(), st.azimuth.end(), 0) -
                                              st.azimuth.begin());
  ASSERT_LT(first, st.azimuth.size());
  // Firing time of laser l in block b (1-based in the manuals) relative to the packet's t0 [us].
  const auto firing_us = [&](int b, int l) {
    if (s.model == "pandarxt32") return 5.632 - 50.0 * (8 - b) + 0.368 + 1.512 * (l - 1);
    if (s.model == "pandar40p") {
      // Pandar40P manual, table "Laser Firing Time of Each Channel": laser ID -> us before the
      // block's end; blocks end at t0 - 28.58 - 55.56 * (10 - b).
      static const std::map<int, double> before_end = {
          {1, 42.22}, {4, 3.62}, {8, 54.67}, {21, 23.89}, {40, 3.62}};
      return -28.58 - 55.56 * (10 - b) - before_end.at(l);
    }
    // Pandar64 manual: t_end - (1.304 a + 1.968 b + 3.62) us; blocks end at
    // t0 - 42.58 - 55.56 * (6 - b). Laser 51: a = b = 0; laser 45: a = 1; laser 12: 54.668.
    static const std::map<int, double> before_end = {
        {51, 3.62}, {45, 4.924}, {12, 54.668}, {1, 23.18}, {64, 12.748}};
    return -42.58 - 55.56 * (6 - b) - before_end.at(l);
  };
  const std::vector<int> lasers = s.model == "pandarxt32"  ? std::vector<int>{1, 2, 17, 32}
                                  : s.model == "pandar40p" ? std::vector<int>{1, 4, 8, 21, 40}
                                                           : std::vector<int>{1, 12, 45, 51, 64};
  const auto index = [&](int k, int b, int l) {
    return (static_cast<std::size_t>(k) * s.blocks() + b - 1) * s.lasers() + l - 1;
  };
  // Absolute time of a point [s] from the packet's t0 and the manual's tables.
  const auto when = [&](int k, int b, int l) {
    return (st.time[first + k] - st.time[first]) * 1e-9 + firing_us(b, l) * 1e-6;
  };
  const std::size_t reference = index(0, 1, lasers[0]);
  EXPECT_GE(*std::min_element(scan.time.begin(), scan.time.end()), 0.f);
  for (const int k : {0, 1, packets_per_rotation - 1})
    for (int b = 1; b <= s.blocks(); ++b)
      for (const int l : lasers) {
        const std::size_t i = index(k, b, l);
        ASSERT_EQ(scan.ring[i], l - 1);
        const int az = (st.azimuth[first + k] + (b - 1) * s.azimuthStep()) % 36000;
        ASSERT_LT(
            (scan.points[i].cast<double>() - expectedHesaiPoint(az, l - 1, (2500 + l - 1) * 0.004))
                .norm(),
            1e-4)
            << "packet " << k << " block " << b << " laser " << l;
        ASSERT_NEAR(scan.time[i] - scan.time[reference], when(k, b, l) - when(0, 1, lasers[0]),
                    2e-7)
            << "packet " << k << " block " << b << " laser " << l;
      }
  // The stamp is the earliest point's time (no capture time given: the sensor's clock).
  const double earliest_s = *std::min_element(scan.time.begin(), scan.time.end());
  EXPECT_EQ(earliest_s, 0.0);
  EXPECT_NEAR((scan.stamp_ns - st.time[first]) * 1e-9 + scan.time[reference],
              firing_us(1, lasers[0]) * 1e-6, 2e-7);
}

INSTANTIATE_TEST_SUITE_P(Hesai, HesaiModels,
                         ::testing::Values("pandarxt32", "pandar40p", "pandar64"));

// Dual return (0x39, last + strongest): per laser the blocks of a round hold a far weak return
// and a near strong one, or twice the same return.
HesaiUnit dualUnit(int block, int laser) {
  if (laser % 5 == 0) return {2000, 50};                  // identical in both blocks
  if (block % 2 == 0) return {3000, 10};                  // last: far and weak
  return {static_cast<std::uint16_t>(1000 + laser), 90};  // strongest: near
}

TEST(HesaiDual, ReturnsAndSelection) {
  socc::testing::TempDir dir;
  HesaiSpec s;
  s.model = "pandar64";
  s.return_mode = 0x39;
  SensorConfig config;
  config.model = s.model;
  config.calibration = dir.write("angles.csv", test_packets::hesaiCalibrationCsv(64));
  const int rounds_per_rotation = 36000 / s.azimuthStep();
  const int packets = 2 * rounds_per_rotation / 3 + 10;  // 3 rounds a packet
  const HesaiStream st = hesaiStream(s, 0, packets, dualUnit);
  const std::size_t identical = 13;  // lasers 0, 5, ... 60: one point per round
  std::map<ReturnMode, std::size_t> points;
  for (const ReturnMode mode :
       {ReturnMode::kAll, ReturnMode::kStrongest, ReturnMode::kFirst, ReturnMode::kLast}) {
    config.returns = mode;
    const HesaiDecoded d = decodeHesai(config, st.packets);
    ASSERT_EQ(d.scans.size(), 1u);
    const SensorScan& scan = d.scans[0];
    points[mode] = scan.size();
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const double r = scan.points[i].norm();
      if (scan.ring[i] % 5 == 0) {
        ASSERT_NEAR(r, 8.0, 1e-4);
        ASSERT_EQ(scan.return_index[i], 0);
        continue;
      }
      const bool far = std::abs(r - 12.0) < 1e-4;
      if (mode == ReturnMode::kAll) {
        ASSERT_EQ(scan.return_index[i], far ? 1 : 0);  // 0: the strongest
      } else {
        ASSERT_EQ(far, mode == ReturnMode::kLast);  // strongest = first = the near one here
      }
    }
  }
  const std::size_t rounds = static_cast<std::size_t>(rounds_per_rotation);
  EXPECT_EQ(points[ReturnMode::kAll], rounds * (2 * 64 - identical));
  EXPECT_EQ(points[ReturnMode::kStrongest], rounds * 64);
  EXPECT_EQ(points[ReturnMode::kFirst], rounds * 64);
  EXPECT_EQ(points[ReturnMode::kLast], rounds * 64);
}

TEST(HesaiCut, SweepsStartAtTheCutAzimuth) {
  HesaiSpec s;  // PandarXT32, nominal angles (no calibration file)
  SensorConfig config;
  config.model = s.model;
  config.cut_azimuth_deg = 90.0;
  const HesaiStream st = hesaiStream(s, 0, 700);  // 2.8 rotations
  const HesaiDecoded d = decodeHesai(config, st.packets);
  ASSERT_EQ(d.scans.size(), 2u);
  for (const SensorScan& scan : d.scans) {
    // Hesai azimuth (clockwise from the front) of the first and last points.
    const auto azimuth = [&](std::size_t i) {
      const double a = std::atan2(-scan.points[i].y(), scan.points[i].x()) * 180 / M_PI;
      return a < 0 ? a + 360 : a;
    };
    EXPECT_NEAR(azimuth(0), 90.0, 0.18);
    EXPECT_NEAR(azimuth(scan.size() - 1), 90.0 - 0.18, 0.18);
    EXPECT_EQ(scan.size(), 2000u * 32u);
    EXPECT_NEAR(scan.time.back(), 0.1, 1e-3);
  }
}

SensorConfig xt32() {
  SensorConfig config;
  config.model = "pandarxt32";
  return config;
}

class HesaiBadInput : public ::testing::Test {
 protected:
  HesaiSpec s;  // PandarXT32
  SensorConfig config = xt32();
  HesaiStream st = hesaiStream(s, 0, 600);  // 2.4 rotations: one complete
};

TEST_F(HesaiBadInput, LostPacketsAreCountedAndLongGapsDropTheSweep) {
  std::vector<Packet> one_lost = st.packets;
  one_lost.erase(one_lost.begin() + 400);  // 1.44 deg: tolerated
  HesaiDecoded d = decodeHesai(config, one_lost);
  EXPECT_EQ(d.stats.gaps, 1u);
  ASSERT_EQ(d.scans.size(), 1u);
  EXPECT_TRUE(d.scans[0].complete);
  std::vector<Packet> many_lost = st.packets;
  many_lost.erase(many_lost.begin() + 400, many_lost.begin() + 410);  // 14.4 deg
  d = decodeHesai(config, many_lost);
  EXPECT_EQ(d.stats.gaps, 10u);
  EXPECT_TRUE(d.scans.empty());
  config.keep_partial = true;
  d = decodeHesai(config, many_lost);
  ASSERT_EQ(d.scans.size(), 3u);
  EXPECT_FALSE(d.scans[1].complete);
}

TEST_F(HesaiBadInput, ReorderedAndDuplicatedPacketsAreLate) {
  std::vector<Packet> packets = st.packets;
  std::swap(packets[300], packets[301]);
  packets.insert(packets.begin() + 350, packets[349]);
  const HesaiDecoded d = decodeHesai(config, packets);
  EXPECT_EQ(d.stats.late, 2u);
  ASSERT_EQ(d.scans.size(), 1u);
  EXPECT_TRUE(d.scans[0].complete);  // the reordered packet is a 0.14 deg hole
}

TEST_F(HesaiBadInput, DamagedPacketsAreCountedDrops) {
  std::vector<Packet> packets = st.packets;
  const std::size_t tail = 12 + 8 * 130;
  Packet truncated = packets[10];
  truncated.data.resize(900);
  Packet bad_mode = packets[11];
  bad_mode.data[tail + 10] = 0x99;
  Packet bad_returns = packets[12];
  bad_returns.data[10] = 2;  // header says dual, tail says strongest
  Packet bad_azimuth = packets[13];
  bad_azimuth.data[12 + 130] = 0xff;  // block 2 azimuth > 360 deg
  bad_azimuth.data[12 + 131] = 0xff;
  Packet bad_date = packets[14];
  bad_date.data[tail + 14] = 13;  // month 13
  Packet too_fast = packets[15];  // motor at 1200 rpm cannot give 0.18 deg per 50 us
  too_fast.data[tail + 11] = 1200 & 0xff;
  too_fast.data[tail + 12] = 1200 >> 8;
  Packet junk;
  junk.data.assign(1080, 0xab);
  packets.insert(packets.begin() + 20,
                 {truncated, bad_mode, bad_returns, bad_azimuth, bad_date, too_fast, junk});
  const HesaiDecoded d = decodeHesai(config, packets);
  EXPECT_EQ(d.stats.malformed, 5u);
  EXPECT_EQ(d.stats.foreign, 2u);
  EXPECT_EQ(d.stats.packets, st.packets.size());
  ASSERT_EQ(d.scans.size(), 1u);
  for (const auto& p : d.scans[0].points) ASSERT_LT(p.norm(), 10.3f);  // all 10 m + 4 mm * laser
}

TEST_F(HesaiBadInput, PacketsOfAnotherModelAreRefused) {
  socc::testing::TempDir dir;
  HesaiSpec p40;
  p40.model = "pandar40p";
  const HesaiStream other = hesaiStream(p40, 0, 60);
  auto decoder = makeHesaiDecoder(config);
  std::vector<SensorScan> scans;
  try {
    for (const Packet& p : other.packets) decoder->feed(p, scans);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("pandar40p"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(scans.empty());
  EXPECT_EQ(detectHesaiModel(other.packets[0].data), "pandar40p");
  // A stream of no Hesai model at all: refused too, after as many packets.
  decoder = makeHesaiDecoder(config);
  Packet junk;
  junk.data.assign(1206, 0x5a);
  try {
    for (int i = 0; i < 60; ++i) decoder->feed(junk, scans);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("none of the first 50 packets"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(detectHesaiModel(st.packets[0].data), "pandarxt32");
}

TEST(HesaiCalibration, WrongFilesAreRefusedWithTheirReason) {
  socc::testing::TempDir dir;
  const auto message = [&](const std::string& model, const std::string& csv) {
    SensorConfig c;
    c.model = model;
    if (!csv.empty()) c.calibration = dir.write("angles.csv", csv);
    try {
      makeHesaiDecoder(c);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("pandar40p", test_packets::hesaiCalibrationCsv(40)), "no error");
  EXPECT_NE(message("pandar40p", test_packets::hesaiCalibrationCsv(32)).find("32 channels"),
            std::string::npos);
  EXPECT_NE(message("pandarxt32", test_packets::hesaiCalibrationCsv(40)).find("another model"),
            std::string::npos);
  EXPECT_NE(message("pandar64", "").find("angle-correction CSV"), std::string::npos);
  std::string damaged = test_packets::hesaiCalibrationCsv(32);
  damaged.replace(damaged.find("\n3,") + 3, 1, "x");
  EXPECT_NE(message("pandarxt32", damaged).find(":4:"), std::string::npos);
  std::string twice = test_packets::hesaiCalibrationCsv(32);
  twice.replace(twice.find("\n3,") + 1, 1, "2");
  EXPECT_NE(message("pandarxt32", twice).find("twice"), std::string::npos);
  EXPECT_NE(message("pandarxt32", "Channel,Elevation,Azimuth\n1,95,0\n").find("implausible"),
            std::string::npos);
  EXPECT_NE(message("pandar128", "").find("unknown"), std::string::npos);
}

TEST(HesaiModelNames, Listed) {
  EXPECT_EQ(hesaiModels(), (std::vector<std::string>{"pandarxt32", "pandar40p", "pandar64"}));
  EXPECT_TRUE(isHesaiModel("pandar64"));
  EXPECT_FALSE(isHesaiModel("os1-64"));
}

}  // namespace
}  // namespace socc::sensors
