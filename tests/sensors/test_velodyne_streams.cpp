// Velodyne streams as they go wrong: dual-return selection, another model than configured, a
// second sensor on the port, lost and reordered packets. A clear error or a counted drop; never
// a crash, never a point that was not in the packets.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <memory>

#include "../temp_dir.hpp"
#include "raw_sensor_data.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/sensors/sensor_config.hpp"
#include "velodyne_model_cases.hpp"

namespace socc::sensors {
namespace {

struct StreamRun {
  std::vector<SensorScan> scans;
  DecodeStats stats;
  std::string model;
};

StreamRun run(SensorConfig config, const std::vector<Packet>& packets) {
  config.keep_partial = true;
  std::unique_ptr<ScanDecoder> decoder = makeDecoder(config);
  StreamRun r;
  for (const Packet& p : packets) decoder->feed(p, r.scans);
  decoder->flush(r.scans);
  r.stats = decoder->stats();
  r.model = decoder->model();
  return r;
}

SensorConfig model(const std::string& name) {
  SensorConfig c;
  c.model = name;
  return c;
}

std::size_t pointCount(const StreamRun& r) {
  std::size_t n = 0;
  for (const SensorScan& s : r.scans) n += s.size();
  return n;
}

// Only distances and reflectivities that were sent (rawOf of a block and channel).
void expectOnlySentPoints(const StreamRun& r, double resolution, std::size_t packets) {
  for (const SensorScan& s : r.scans)
    for (std::size_t i = 0; i < s.size(); ++i) {
      const long raw = std::lround(s.points[i].norm() / resolution);
      ASSERT_TRUE(raw >= 1500 && raw < 1500 + 12 * 32) << raw;
      ASSERT_LT(s.intensity[i], static_cast<float>(packets));
    }
}

// 40 dual-return packets of model m: even channels one echo (2 m, reflectivity 50, both blocks
// alike), odd channels the strongest return 2 m bright (200) and the last 3 m weak (10), held
// by the blocks b with last_block(b). The packet's last two bytes are type and value.
std::vector<Packet> dualPackets(const test::ModelCase& m,
                                const std::function<bool(int)>& last_block, std::uint8_t type,
                                std::uint8_t value) {
  std::vector<Packet> packets;
  for (int k = 0; k < 40; ++k) {
    const double stamp = 1e6 + k * m.period_us;
    std::vector<test::BlockSpec> blocks;
    for (int b = 0; b < 12; ++b) {
      const auto az = static_cast<std::uint16_t>(
          std::lround(test::kHundredthsPerUs * (stamp + m.block_start(b))) % 36000);
      blocks.push_back({m.flag(b), az, [last = last_block(b)](int c) {
                          if (c % 2 == 0) return test::Echo{2000, 50};
                          return last ? test::Echo{1500, 10} : test::Echo{1000, 200};
                        }});
    }
    packets.push_back(test::velodynePacket(blocks, static_cast<std::uint32_t>(stamp), type, value,
                                           static_cast<std::int64_t>(stamp * 1000.0) + 2'000'000));
  }
  return packets;
}

// VLP-16 dual return (manual: even blocks the last return, odd blocks the strongest, or the
// second strongest when it is the last; identical when there was one echo).
std::vector<Packet> vlp16DualPackets() {
  const test::ModelCase m = test::vlp16(true);
  return dualPackets(
      m, [](int b) { return b % 2 == 0; }, m.mode, m.product);
}

TEST(VelodyneStreams, DualReturnSelection) {
  const std::vector<Packet> packets = vlp16DualPackets();
  const std::size_t firings = packets.size() * 6 * 32;  // 6 block pairs of 32 channels
  SensorConfig all = model("vlp16");
  const StreamRun both = run(all, packets);
  EXPECT_EQ(pointCount(both), firings / 2 + firings);  // one echo, or two distinct returns
  SensorConfig strongest = model("vlp16");
  strongest.returns = ReturnMode::kStrongest;
  const StreamRun s = run(strongest, packets);
  ASSERT_EQ(pointCount(s), firings);
  for (const SensorScan& scan : s.scans)
    for (std::size_t i = 0; i < scan.size(); ++i)
      ASSERT_TRUE(scan.intensity[i] == 200.0f || scan.intensity[i] == 50.0f) << scan.intensity[i];
  SensorConfig last = model("vlp16");
  last.returns = ReturnMode::kLast;
  const StreamRun l = run(last, packets);
  ASSERT_EQ(pointCount(l), firings);
  for (const SensorScan& scan : l.scans)
    for (std::size_t i = 0; i < scan.size(); ++i)
      ASSERT_TRUE(scan.intensity[i] == 10.0f || scan.intensity[i] == 50.0f) << scan.intensity[i];
  SensorConfig first = model("vlp16");
  first.returns = ReturnMode::kFirst;
  EXPECT_THROW(makeDecoder(first), std::runtime_error);
}

// HDL-64E S3 dual return: per firing, upper and lower block of the strongest return, then of
// the last (or the second strongest when it is the last; identical when there was one echo).
std::vector<Packet> hdl64DualPackets() {
  // The HDL-64E's last two bytes are status bytes (no return-mode byte): any pair.
  return dualPackets(
      test::hdl64e(true), [](int b) { return b % 4 >= 2; }, 0x41, 0x30);
}

SensorConfig hdl64Config() {
  SensorConfig c = model("hdl64e");
  c.calibration = socc::testing::processTempDir() / "hdl64e.yaml";
  test::writeYamlCalibration(c.calibration, test::hdl64e(true).vert_deg, 0.002);
  return c;
}

TEST(VelodyneStreams, Hdl64DualReturnSelection) {
  const std::vector<Packet> packets = hdl64DualPackets();
  const std::size_t firings = packets.size() * 3 * 64;  // 3 firings of 64 lasers a packet
  const StreamRun both = run(hdl64Config(), packets);
  EXPECT_EQ(both.stats.packets, packets.size());
  EXPECT_EQ(pointCount(both), firings / 2 + firings);  // one echo, or two distinct returns
  std::size_t lower = 0;
  for (const SensorScan& scan : both.scans)
    for (std::size_t i = 0; i < scan.size(); ++i) {
      lower += scan.ring[i] >= 32 ? 1 : 0;
      // Return index 1 (last) only on the odd channels, where the returns differ.
      if (scan.return_index[i] == 1) {
        ASSERT_EQ(scan.intensity[i], 10.0f);
      }
    }
  EXPECT_EQ(lower, pointCount(both) / 2);
  for (const auto& [mode, kept] :
       {std::pair{ReturnMode::kStrongest, 200.0f}, std::pair{ReturnMode::kLast, 10.0f}}) {
    SensorConfig c = hdl64Config();
    c.returns = mode;
    const StreamRun r = run(c, packets);
    ASSERT_EQ(pointCount(r), firings);
    for (const SensorScan& scan : r.scans)
      for (std::size_t i = 0; i < scan.size(); ++i)
        ASSERT_TRUE(scan.intensity[i] == kept || scan.intensity[i] == 50.0f) << scan.intensity[i];
  }
}

// The dual stream detected as such (equal azimuths over a firing's 4 blocks, a packet every
// 172.8 us) and the single stream as single; an HDL-64E stream refused as any other model and
// another model's stream refused as an HDL-64E, with the measured facts.
TEST(VelodyneStreams, Hdl64ModelChecks) {
  SensorConfig detect = hdl64Config();
  detect.model.clear();
  EXPECT_EQ(run(detect, test::makePackets(test::hdl64e(true), 40, 1'000'000u)).model, "hdl64e");
  EXPECT_EQ(run(detect, test::makePackets(test::hdl64e(false), 40, 1'000'000u)).model, "hdl64e");
  const std::vector<Packet> dual = test::makePackets(test::hdl64e(true), 40, 1'000'000u);
  for (const char* other : {"vlp16", "vlp32c", "hdl32e"}) {
    try {
      run(model(other), dual);
      FAIL() << "HDL-64E packets decoded as a " << other;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("upper/lower blocks FF EE / FF DD (HDL-64E)"), std::string::npos) << what;
      EXPECT_NE(what.find("dual return pairs"), std::string::npos) << what;
    }
  }
  try {
    run(hdl64Config(), test::makePackets(test::hdl32e(), 40, 1'000'000u));
    FAIL() << "HDL-32E packets decoded as an HDL-64E";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("do not come from a hdl64e"), std::string::npos)
        << e.what();
  }
  // The S2 Appendix G timing (23.3 us a block pair, a packet every 139.8 us) is not an
  // HDL-64E's packet rate: refused with the measured period.
  test::ModelCase fast = test::hdl64e(false);
  fast.period_us = 6 * 23.296;
  fast.block_start = [](int b) { return -419.3 + 23.296 * (b / 2); };
  try {
    run(hdl64Config(), test::makePackets(fast, 40, 1'000'000u));
    FAIL() << "a packet every 139.8 us accepted as an HDL-64E";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a packet comes every 140.0 us"), std::string::npos)
        << e.what();
  }
}

TEST(VelodyneStreams, RefusesPacketsOfAnotherModel) {
  const std::vector<Packet> hdl32 = test::makePackets(test::hdl32e(), 40, 5'000'000u);
  try {
    run(model("vlp16"), hdl32);
    FAIL() << "HDL-32E packets decoded as a VLP-16";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("do not come from a vlp16"), std::string::npos) << what;
    EXPECT_NE(what.find("look like a hdl32e"), std::string::npos) << what;
  }
  EXPECT_THROW(run(model("vlp32c"), hdl32), std::runtime_error);
  EXPECT_THROW(run(model("vls128"), test::makePackets(test::vlp32c(), 40, 5'000'000u)),
               std::runtime_error);
}

TEST(VelodyneStreams, DetectsTheModelFromTheStreamNotTheFactoryByte) {
  EXPECT_EQ(run(SensorConfig{}, test::makePackets(test::hdl32e(), 40, 1'000'000u)).model, "hdl32e");
  EXPECT_EQ(run(SensorConfig{}, test::makePackets(test::vlp32c(), 40, 1'000'000u)).model, "vlp32c");
  // A VLP-16 whose factory byte says HDL-32E (as in the real capture) is still a VLP-16.
  std::vector<Packet> lying = test::makePackets(test::vlp16(false), 40, 1'000'000u);
  for (Packet& p : lying) p.data[1205] = 0x21;
  std::unique_ptr<ScanDecoder> d = makeDecoder(SensorConfig{});
  std::vector<SensorScan> out;
  for (const Packet& p : lying) d->feed(p, out);
  EXPECT_EQ(d->model(), "vlp16");
  EXPECT_NE(d->notes().find("factory byte 0x21 (hdl32e) disagrees"), std::string::npos)
      << d->notes();
}

TEST(VelodyneStreams, RealVlp16RefusedAsAnHdl32e) {
  SOCC_REQUIRE_RAW_SENSORS();
  RecordingOptions o;
  o.sensor.model = "hdl32e";
  std::unique_ptr<ScanStream> stream = openRecording(test::vlp16Pcap(), o);
  try {
    stream->next();
    FAIL() << "a VLP-16 capture decoded as an HDL-32E";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("do not come from a hdl32e"), std::string::npos) << what;
    EXPECT_NE(what.find("1327"), std::string::npos) << what;  // the measured packet period
    EXPECT_NE(what.find("look like a vlp16"), std::string::npos) << what;
  }
}

TEST(VelodyneStreams, LostAndReorderedPacketsAreCountedNotDecodedAsGarbage) {
  const test::ModelCase m = test::vlp16(false);
  std::vector<Packet> packets = test::makePackets(m, 200, 2'000'000u);
  const StreamRun clean = run(model("vlp16"), packets);
  packets.erase(packets.begin() + 120, packets.begin() + 122);  // two lost
  std::swap(packets[60], packets[61]);                          // one late
  const StreamRun damaged = run(model("vlp16"), packets);
  EXPECT_EQ(damaged.stats.late, 1u);
  EXPECT_EQ(damaged.stats.gaps, 3u);  // the two lost, and the late one's gap when it was missing
  EXPECT_EQ(damaged.stats.packets, 197u);
  EXPECT_EQ(pointCount(damaged), pointCount(clean) - 3 * 12 * 32);
  expectOnlySentPoints(damaged, 0.002, 200);
  for (const SensorScan& s : damaged.scans)
    for (std::size_t i = 1; i < s.size(); ++i) ASSERT_GE(s.time[i], s.time[i - 1]);
}

TEST(VelodyneStreams, SecondSensorOnThePortIsSkipped) {
  const std::vector<Packet> ours = test::makePackets(test::vlp16(false), 120, 2'000'000u);
  std::vector<Packet> other = test::makePackets(test::hdl32e(), 120, 7'000'000u);
  std::vector<Packet> mixed;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    mixed.push_back(ours[i]);
    other[i].source_ipv4 = 0xC0A801CA;  // 192.168.1.202
    mixed.push_back(other[i]);
  }
  const StreamRun alone = run(model("vlp16"), ours);
  const StreamRun shared = run(model("vlp16"), mixed);
  EXPECT_EQ(shared.stats.other_sender, other.size());
  EXPECT_EQ(shared.stats.packets, ours.size());
  ASSERT_EQ(shared.scans.size(), alone.scans.size());
  for (std::size_t i = 0; i < alone.scans.size(); ++i)
    EXPECT_EQ(shared.scans[i].points, alone.scans[i].points);
}

TEST(VelodyneStreams, MalformedPacketsAreSkipped) {
  std::vector<Packet> packets = test::makePackets(test::vlp16(false), 60, 2'000'000u);
  packets[30].data[2] = 0xFF;  // azimuth 0xFFxx > 35999
  packets[30].data[3] = 0xFF;
  packets[31].data[100] = 0x12;  // a damaged block flag
  packets[32].data.resize(700);  // cut short: not a data packet
  const StreamRun r = run(model("vlp16"), packets);
  EXPECT_EQ(r.stats.malformed, 2u);
  EXPECT_EQ(r.stats.foreign, 1u);
  expectOnlySentPoints(r, 0.002, 60);
}

TEST(VelodyneStreams, WrongCalibrationFiles) {
  SOCC_REQUIRE_RAW_SENSORS();
  // A VLP-32C calibration for a VLP-16 stream, and the other way round.
  RecordingOptions o;
  o.sensor.model = "vlp16";
  o.sensor.calibration = test::vlp32cDir() / "VLP32.yaml";
  try {
    openRecording(test::vlp16Pcap(), o)->next();
    FAIL() << "VLP32.yaml accepted for a VLP-16";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("wrong calibration file"), std::string::npos) << e.what();
  }
  SensorConfig c = model("vlp32c");
  c.calibration = test::vlp16Xml();
  const std::vector<Packet> p32 = test::makePackets(test::vlp32c(), 40, 1'000'000u);
  EXPECT_THROW(run(c, p32), std::runtime_error);
  // Not a calibration at all.
  c.calibration = socc::testing::processTempDir() / "garbage.yaml";
  std::ofstream(c.calibration) << "lasers: [1, 2, {x: ]]\n";
  EXPECT_THROW(makeDecoder(c), std::runtime_error);
  c.calibration = socc::testing::processTempDir() / "garbage.xml";
  std::ofstream(c.calibration) << "<boost_serialization><DB><points_><item><px><id_>zero";
  EXPECT_THROW(makeDecoder(c), std::runtime_error);
  c.calibration = "/nonexistent/calibration.yaml";
  EXPECT_THROW(makeDecoder(c), std::runtime_error);
}

TEST(VelodyneStreams, UnknownModelNamesTheKnownOnes) {
  try {
    makeDecoder(model("vlp17"));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("vlp16, vlp32c, hdl32e, hdl64e, vls128"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(makeDecoder(model("hdl64e")),
               std::runtime_error);  // no calibration: every unit differs
}

}  // namespace
}  // namespace socc::sensors
