// Several sensors on one UDP port (SensorConfig::sensor_address, --sensor-address): a stream
// decodes one sender, the selected one or the first; the packets of every other sender are
// dropped before decoding, counted and reported once per address. In a capture that interleaves
// the real VLP-16 recording with two synthetic sensors, and live on 127.0.0.1.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>

#include "../temp_dir.hpp"
#include "pcap_writer.hpp"
#include "raw_sensor_data.hpp"
#include "socc/sensors/decoded_scan_stream.hpp"
#include "socc/sensors/pcap_source.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/sensors/udp_source.hpp"
#include "velodyne_model_cases.hpp"

namespace socc::sensors {
namespace {

constexpr std::uint32_t kRealSensor = 0xC0A801C8;   // 192.168.1.200, the capture's VLP-16
constexpr std::uint32_t kSecondVlp16 = 0xC0A801CA;  // 192.168.1.202
constexpr std::uint32_t kHdl32e = 0xC0A801CB;       // 192.168.1.203

std::vector<Packet> readPackets(const std::filesystem::path& file) {
  std::unique_ptr<PacketSource> source = openPcap(file, 2368);
  std::vector<Packet> packets;
  while (std::optional<Packet> p = source->next()) packets.push_back(std::move(*p));
  return packets;
}

// Synthetic packets from `sender`, arriving from first_ns on.
std::vector<Packet> fromSender(const test::ModelCase& m, int count, std::uint32_t sender,
                               std::int64_t first_ns) {
  std::vector<Packet> packets = test::makePackets(m, count, 3'000'000u);
  const std::int64_t t0 = packets.front().stamp_ns;
  for (Packet& p : packets) {
    p.source_ipv4 = sender;
    p.stamp_ns += first_ns - t0;
  }
  return packets;
}

std::vector<Packet> byArrival(std::vector<std::vector<Packet>> streams) {
  std::vector<Packet> all;
  for (std::vector<Packet>& s : streams) all.insert(all.end(), s.begin(), s.end());
  std::stable_sort(all.begin(), all.end(),
                   [](const Packet& a, const Packet& b) { return a.stamp_ns < b.stamp_ns; });
  return all;
}

std::filesystem::path writeCapture(const std::filesystem::path& dir, const std::string& name,
                                   const std::vector<Packet>& packets) {
  const std::filesystem::path file = dir / name;
  test::PcapWriter w(file);
  for (const Packet& p : packets) w.udp(p.stamp_ns, p.data, 2368, p.source_ipv4);
  return file;
}

struct SenderRun {
  std::vector<SensorScan> scans;
  std::string problems;
  std::vector<std::string> notices;
};

SenderRun decodeCapture(const std::filesystem::path& file, const std::string& model,
                        const std::string& address) {
  SenderRun d;
  RecordingOptions o;
  o.sensor.model = model;
  o.sensor.keep_partial = true;
  o.sensor.sensor_address = address;
  o.sensor.notify = [&d](const std::string& m) { d.notices.push_back(m); };
  std::unique_ptr<ScanStream> stream = openRecording(file, o);
  while (std::optional<SensorScan> s = stream->next()) d.scans.push_back(std::move(*s));
  d.problems = stream->problems();
  return d;
}

void expectSamePoints(const std::vector<SensorScan>& got, const std::vector<SensorScan>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(got[i].points, want[i].points) << i;
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The captures are written once for the suite: the first 600 packets of the real VLP-16 (0.8 s,
// 8 turns) alone, a synthetic VLP-16 (0.4 s) alone, a synthetic HDL-32E (0.22 s) alone, and all
// three interleaved.
class TwoSendersCapture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!std::filesystem::exists(test::rawSensors())) return;
    std::vector<Packet> real = readPackets(test::vlp16Pcap());
    real.resize(600);
    const std::int64_t t0 = real.front().stamp_ns + 300'000;  // the others start a bit later
    const std::vector<Packet> second = fromSender(test::vlp16(false), 300, kSecondVlp16, t0);
    const std::vector<Packet> hdl = fromSender(test::hdl32e(), 400, kHdl32e, t0 + 150'000);
    // A private directory: ctest runs each case as its own process, in parallel.
    dir_ = std::make_unique<socc::testing::TempDir>();
    real_ = writeCapture(dir_->path(), "real.pcap", real);
    second_ = writeCapture(dir_->path(), "second.pcap", second);
    hdl_ = writeCapture(dir_->path(), "hdl.pcap", hdl);
    mixed_ = writeCapture(dir_->path(), "three_senders.pcap", byArrival({real, second, hdl}));
  }
  static void TearDownTestSuite() { dir_.reset(); }
  void SetUp() override { SOCC_REQUIRE_RAW_SENSORS(); }
  static inline std::unique_ptr<socc::testing::TempDir> dir_;
  static inline std::filesystem::path real_, second_, hdl_, mixed_;
};

// No selection: the first sender (the real VLP-16) is decoded exactly as alone; the other two
// are dropped, counted and each reported once with its address.
TEST_F(TwoSendersCapture, FirstSenderIsDecodedOthersReportedOnce) {
  const SenderRun alone = decodeCapture(real_, "vlp16", "");
  const SenderRun mixed = decodeCapture(mixed_, "vlp16", "");
  expectSamePoints(mixed.scans, alone.scans);
  ASSERT_EQ(mixed.notices.size(), 2u);
  EXPECT_NE(mixed.notices[0].find("192.168.1.202"), std::string::npos) << mixed.notices[0];
  EXPECT_NE(mixed.notices[0].find("decodes 192.168.1.200"), std::string::npos);
  EXPECT_NE(mixed.notices[1].find("192.168.1.203"), std::string::npos) << mixed.notices[1];
  EXPECT_NE(mixed.problems.find("700 packets of other senders on the port (dropped)"),
            std::string::npos)
      << mixed.problems;
  EXPECT_NE(mixed.problems.find("300 packets from 192.168.1.202, 400 packets from 192.168.1.203"),
            std::string::npos)
      << mixed.problems;
  EXPECT_EQ(countOf(mixed.problems, "192.168.1.203"), 1u) << mixed.problems;  // once
}

// A detected model: the stream locks onto the first sender the detection takes, the others are
// never mixed into its sweeps.
TEST_F(TwoSendersCapture, DetectedModelNeverMixesSenders) {
  const SenderRun alone = decodeCapture(real_, "", "");
  const SenderRun mixed = decodeCapture(mixed_, "", "");
  expectSamePoints(mixed.scans, alone.scans);
  EXPECT_EQ(mixed.notices.size(), 2u);
}

// --sensor-address picks a sender: the second VLP-16 or the HDL-32E (another model, detected),
// decoded exactly as from a capture of that sensor alone.
TEST_F(TwoSendersCapture, SelectedSenderIsDecodedAsAlone) {
  const SenderRun second = decodeCapture(mixed_, "vlp16", "192.168.1.202");
  const SenderRun second_alone = decodeCapture(second_, "vlp16", "");
  ASSERT_GE(second_alone.scans.size(), 4u);
  expectSamePoints(second.scans, second_alone.scans);
  ASSERT_EQ(second.notices.size(), 2u);
  EXPECT_NE(second.notices[0].find("not the selected sensor address 192.168.1.202"),
            std::string::npos)
      << second.notices[0];

  const SenderRun hdl = decodeCapture(mixed_, "", "192.168.1.203");
  const SenderRun hdl_alone = decodeCapture(hdl_, "", "");
  ASSERT_GE(hdl_alone.scans.size(), 3u);
  expectSamePoints(hdl.scans, hdl_alone.scans);
  for (const SensorScan& s : hdl.scans)
    for (const std::uint16_t r : s.ring) ASSERT_LT(r, 32);
}

TEST_F(TwoSendersCapture, AnAddressWithoutPacketsOrNotAnAddressIsAClearError) {
  try {
    decodeCapture(mixed_, "vlp16", "10.1.2.3");
    FAIL() << "no packet from 10.1.2.3, yet no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no packet came from the sensor address 10.1.2.3"), std::string::npos)
        << what;
    EXPECT_NE(what.find("600 packets from 192.168.1.200"), std::string::npos) << what;
  }
  EXPECT_THROW(decodeCapture(mixed_, "vlp16", "192.168.1"), std::runtime_error);
  RecordingOptions bag;
  bag.sensor.sensor_address = "192.168.1.201";
  EXPECT_THROW(openRecording(test::vlp32cDir(), bag), std::runtime_error);
}

// Live: two senders (127.0.0.2 a VLP-16, 127.0.0.3 an HDL-32E) on one port of 127.0.0.1.
class TwoSendersLive : public ::testing::Test {
 protected:
  static int sender(const char* address) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    ::inet_pton(AF_INET, address, &a.sin_addr);
    EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << address;
    return fd;
  }

  // Sends both streams interleaved in batches and decodes what arrives, packet by packet.
  SenderRun run(const std::string& address) {
    UdpOptions o;
    o.address = "127.0.0.1";
    o.port = 0;
    o.idle_timeout = std::chrono::milliseconds(500);
    const int probe = sender("127.0.0.1");
    socklen_t len = sizeof(sockaddr_in);
    sockaddr_in to{};
    ::getsockname(probe, reinterpret_cast<sockaddr*>(&to), &len);
    ::close(probe);  // a free port of 127.0.0.1, taken by the source just below
    o.port = ntohs(to.sin_port);
    std::unique_ptr<PacketSource> source = openUdp(o);
    SenderRun d;
    SensorConfig config;
    config.model = address == "127.0.0.3" ? "" : "vlp16";
    config.sensor_address = address;
    config.keep_partial = true;
    config.notify = [&d](const std::string& m) { d.notices.push_back(m); };
    std::unique_ptr<ScanDecoder> decoder = makeDecoder(config);
    const int vlp = sender("127.0.0.2"), hdl = sender("127.0.0.3");
    const std::vector<Packet> a = test::makePackets(test::vlp16(false), 240, 3'000'000u);
    const std::vector<Packet> b = test::makePackets(test::hdl32e(), 240, 3'000'000u);
    for (std::size_t i = 0; i < a.size(); i += 20) {
      for (std::size_t j = i; j < i + 20; ++j) {
        ::sendto(vlp, a[j].data.data(), a[j].data.size(), 0, reinterpret_cast<sockaddr*>(&to),
                 sizeof to);
        ::sendto(hdl, b[j].data.data(), b[j].data.size(), 0, reinterpret_cast<sockaddr*>(&to),
                 sizeof to);
      }
      for (int k = 0; k < 40; ++k) {
        std::optional<Packet> p = source->next();
        if (!p) break;
        decoder->feed(*p, d.scans);
      }
    }
    decoder->flush(d.scans);
    ::close(vlp);
    ::close(hdl);
    d.problems = describeDecodeStats(decoder->stats()) + decoder->notes();
    stats_ = decoder->stats();
    return d;
  }
  DecodeStats stats_;
};

TEST_F(TwoSendersLive, FirstSenderOrTheSelectedOneOnly) {
  const SenderRun first = run("");
  EXPECT_EQ(stats_.packets, 240u);
  EXPECT_EQ(stats_.other_sender, 240u);
  ASSERT_EQ(first.notices.size(), 1u);
  EXPECT_NE(first.notices[0].find("dropping the packets of 127.0.0.3"), std::string::npos)
      << first.notices[0];
  EXPECT_NE(first.problems.find("240 packets from 127.0.0.3"), std::string::npos) << first.problems;
  ASSERT_GE(first.scans.size(), 2u);
  for (const SensorScan& s : first.scans)
    for (const std::uint16_t r : s.ring) ASSERT_LT(r, 16);  // VLP-16 lasers only

  const SenderRun selected = run("127.0.0.3");
  EXPECT_EQ(stats_.packets, 240u);
  EXPECT_EQ(stats_.other_sender, 240u);
  ASSERT_EQ(selected.notices.size(), 1u);
  EXPECT_NE(selected.notices[0].find("127.0.0.2"), std::string::npos) << selected.notices[0];
  bool high_ring = false;
  for (const SensorScan& s : selected.scans)
    for (const std::uint16_t r : s.ring) high_ring = high_ring || r >= 16;
  EXPECT_TRUE(high_ring) << "the HDL-32E's 32 lasers";
}

}  // namespace
}  // namespace socc::sensors
