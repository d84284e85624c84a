// Packet transports: pcap captures (libpcap; VLAN tags, IPv4 fragments, damaged files) and live
// UDP on the loopback interface.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <random>

#include "../temp_dir.hpp"
#include "pcap_writer.hpp"
#include "raw_sensor_data.hpp"
#include "socc/sensors/pcap_source.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/sensors/udp_source.hpp"

namespace socc::sensors {
namespace {

std::filesystem::path temp(const std::string& name) {
  return socc::testing::processTempDir() / name;
}

std::vector<std::uint8_t> pattern(std::size_t n, int seed) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i)
    v[i] = static_cast<std::uint8_t>((i * 7 + static_cast<std::size_t>(seed)) & 0xFF);
  return v;
}

TEST(Pcap, PortFilterVlanAndFragments) {
  const std::filesystem::path file = temp("fragments.pcap");
  {
    test::PcapWriter w(file);
    w.udp(1'000'000'000, pattern(1206, 1), 2368);
    w.udp(1'000'100'000, pattern(512, 2), 8308);  // another port
    w.udp(1'000'200'000, pattern(8448, 3), 7502, 0x0A000002, true,
          1480);  // Ouster-sized, fragmented
    w.udp(1'000'300'000, pattern(8448, 4), 7502, 0x0A000002, false, 1480, 2);  // a fragment lost
    w.udp(1'000'400'000, pattern(1206, 5), 2368, 0xC0A801C9, true);            // 802.1Q tagged
  }
  std::unique_ptr<PacketSource> all = openPcap(file, 0);
  std::vector<Packet> got;
  while (std::optional<Packet> p = all->next()) got.push_back(std::move(*p));
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got[0].data, pattern(1206, 1));
  EXPECT_EQ(got[0].stamp_ns, 1'000'000'000);
  EXPECT_EQ(got[0].source_ipv4, 0xC0A801C9u);
  EXPECT_EQ(got[1].destination_port, 8308);
  EXPECT_EQ(got[2].data, pattern(8448, 3));  // reassembled
  EXPECT_EQ(got[2].destination_port, 7502);
  EXPECT_EQ(got[3].data, pattern(1206, 5));
  EXPECT_NE(all->problems().find("1 fragmented datagrams incomplete"), std::string::npos)
      << all->problems();
  std::unique_ptr<PacketSource> velodyne = openPcap(file, 2368);
  int n = 0;
  while (velodyne->next()) ++n;
  EXPECT_EQ(n, 2);
}

TEST(Pcap, NotACaptureIsAClearError) {
  const std::filesystem::path file = temp("not_a_capture.pcap");
  std::ofstream(file) << "this is text, not a capture\n";
  EXPECT_FALSE(isPcap(file));
  EXPECT_THROW(openPcap(file, 0), std::runtime_error);
  try {
    openRecording(file, RecordingOptions{});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a recording socc reads"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(openRecording(temp("missing.pcap"), RecordingOptions{}), std::runtime_error);
}

RecordingOptions vlp16() {
  RecordingOptions o;
  o.sensor.model = "vlp16";
  o.sensor.calibration = test::vlp16Xml();
  o.sensor.keep_partial = true;
  return o;
}

std::vector<std::uint8_t> readFile(const std::filesystem::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A capture cut off mid-record: everything before the cut is decoded, the cut is reported.
TEST(Pcap, TruncatedCaptureKeepsWhatWasRecorded) {
  SOCC_REQUIRE_RAW_SENSORS();
  std::vector<std::uint8_t> bytes = readFile(test::vlp16Pcap());
  bytes.resize(bytes.size() / 2 + 333);
  const std::filesystem::path file = temp("truncated.pcap");
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  std::unique_ptr<ScanStream> s = openRecording(file, vlp16());
  std::size_t scans = 0;
  while (std::optional<SensorScan> scan = s->next()) {
    ++scans;
    for (const Eigen::Vector3f& p : scan->points) ASSERT_TRUE(p.allFinite() && p.norm() < 131.0f);
  }
  EXPECT_GT(scans, 20u);
  EXPECT_LT(scans, 30u);
  EXPECT_NE(s->problems().find("damaged record"), std::string::npos) << s->problems();
}

// Random byte damage anywhere after the file header: no crash, every point finite and within
// the sensor's range; damage is counted.
TEST(Pcap, CorruptedCaptureNeverCrashesNorInventsPoints) {
  SOCC_REQUIRE_RAW_SENSORS();
  const std::vector<std::uint8_t> original = readFile(test::vlp16Pcap());
  std::mt19937 rng(28);
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<std::uint8_t> bytes = original;
    std::uniform_int_distribution<std::size_t> at(24, bytes.size() - 1);
    for (int i = 0; i < 300; ++i) bytes[at(rng)] = static_cast<std::uint8_t>(rng());
    const std::filesystem::path file = temp("corrupted.pcap");
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    try {
      std::unique_ptr<ScanStream> s = openRecording(file, vlp16());
      while (std::optional<SensorScan> scan = s->next())
        for (const Eigen::Vector3f& p : scan->points)
          ASSERT_TRUE(p.allFinite() && p.norm() < 131.0f);
    } catch (const std::runtime_error& e) {
      SUCCEED() << e.what();  // e.g. the model check refuses damaged first packets: a clear error
    }
  }
  // A damaged file header: a clear error when opening.
  std::vector<std::uint8_t> bytes = original;
  bytes[0] = 0x00;
  const std::filesystem::path file = temp("bad_header.pcap");
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  EXPECT_THROW(openRecording(file, vlp16()), std::runtime_error);
}

std::uint16_t freeLoopbackPort() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

TEST(Udp, ReceivesOnLoopbackWithKernelStamps) {
  UdpOptions o;
  o.address = "127.0.0.1";
  o.port = freeLoopbackPort();
  o.idle_timeout = std::chrono::milliseconds(200);
  std::unique_ptr<PacketSource> source = openUdp(o);
  const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(o.port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto before = std::chrono::system_clock::now().time_since_epoch();
  for (int i = 0; i < 50; ++i) {
    const std::vector<std::uint8_t> d = pattern(1206, i);
    ASSERT_EQ(::sendto(tx, d.data(), d.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
              1206);
  }
  ::close(tx);
  for (int i = 0; i < 50; ++i) {
    std::optional<Packet> p = source->next();
    ASSERT_TRUE(p) << i;
    EXPECT_EQ(p->data, pattern(1206, i));
    EXPECT_EQ(p->source_ipv4, 0x7F000001u);
    EXPECT_GE(p->stamp_ns, std::chrono::duration_cast<std::chrono::nanoseconds>(before).count());
  }
  EXPECT_FALSE(source->next());  // idle timeout
  EXPECT_TRUE(source->problems().empty());
}

TEST(Udp, SetupErrorsAreClear) {
  UdpOptions o;
  o.address = "not-an-address";
  EXPECT_THROW(openUdp(o), std::runtime_error);
  o.address = "127.0.0.1";
  o.multicast_group = "10.0.0.1";
  EXPECT_THROW(openUdp(o), std::runtime_error);
  o.multicast_group.clear();
  o.interface = "no-such-interface0";
  EXPECT_THROW(openUdp(o), std::runtime_error);
}

}  // namespace
}  // namespace socc::sensors
