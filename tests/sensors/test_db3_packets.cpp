// The real ROS 2 bags of ../shared/data/raw_sensors (nebula's test recordings): topics, message
// counts and stamps as sqlite3 shows them, and every packet of the VelodyneScan / PandarScan
// messages with its size, first bytes and stamp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "bag_test_data.hpp"
#include "bags/bag_packet_source.hpp"
#include "bags/bag_reader.hpp"
#include "socc/sensors/bag_recording.hpp"

namespace socc::sensors::bags {
namespace {

const std::filesystem::path kVlp32Dir = test::rawSensors() / "03_velodyne_vlp32c_nebula_db3";
const std::filesystem::path kVlp32Db3 = kVlp32Dir / "1713492677464078412_0.db3";
const std::filesystem::path kXt32Dir = test::rawSensors() / "06_hesai_xt32_nebula_db3";
const std::filesystem::path kXt32Db3 = kXt32Dir / "1673400677802009732_0.db3";

std::vector<Packet> allPackets(const std::filesystem::path& bag) {
  std::unique_ptr<BagReader> reader = openBagReader(bag);
  BagPacketSource source(std::move(reader), 0);
  std::vector<Packet> packets;
  while (std::optional<Packet> p = source.next()) packets.push_back(std::move(*p));
  EXPECT_EQ(source.problems(), "");
  return packets;
}

TEST(Db3Bag, Vlp32TopicsAndMessages) {
  SOCC_REQUIRE_DATA(kVlp32Db3);
  std::unique_ptr<BagReader> reader = openBagReader(kVlp32Db3);
  ASSERT_EQ(reader->topics().size(), 1u);
  const TopicInfo& t = reader->topics()[0];
  EXPECT_EQ(t.name, "/sensing/lidar/front/velodyne_packets");
  EXPECT_EQ(t.type, "velodyne_msgs/msg/VelodyneScan");
  EXPECT_EQ(t.encoding, Encoding::kCdr);
  EXPECT_EQ(t.messages, 5u);
  // sqlite3 1713492677464078412_0.db3 'select timestamp, length(data) from messages'
  const std::vector<std::int64_t> stamps = {1713492677464078412, 1713492677545368298,
                                            1713492677630748420, 1713492677730768896,
                                            1713492677841065510};
  const std::vector<std::size_t> sizes = {92452, 92452, 92452, 91236, 92452};
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    const std::optional<BagMessage> m = reader->next();
    ASSERT_TRUE(m);
    EXPECT_EQ(m->stamp_ns, stamps[i]);
    EXPECT_EQ(m->data.size(), sizes[i]);
  }
  EXPECT_FALSE(reader->next());
  EXPECT_EQ(reader->problems(), "");
}

TEST(Db3Bag, Vlp32VelodyneScanPackets) {
  SOCC_REQUIRE_DATA(kVlp32Db3);
  const std::vector<Packet> packets = allPackets(kVlp32Db3);
  ASSERT_EQ(packets.size(), 379u);  // 76 + 76 + 76 + 75 + 76 (message sizes above)
  std::int64_t previous = 0;
  for (const Packet& p : packets) {
    ASSERT_EQ(p.data.size(), 1206u);
    EXPECT_EQ(p.data[0], 0xFF);  // every firing block starts FF EE
    EXPECT_EQ(p.data[1], 0xEE);
    EXPECT_EQ(p.data[1205], 0x28) << "factory byte: VLP-32C";
    EXPECT_GE(p.stamp_ns, previous);
    // Packet stamps lie within the recording (bag start - 0.2 s .. bag end).
    EXPECT_GT(p.stamp_ns, 1713492677464078412 - 200'000'000);
    EXPECT_LT(p.stamp_ns, 1713492677841065510 + 1);
    previous = p.stamp_ns;
  }
  // Each message holds one 10 Hz sweep of the 180 deg field of view (76 packets over 0.1 s,
  // the 50 ms gap is the blanked half); its first packet's stamp is the message header's.
  // Values from decoding the CDR by hand (python struct) from the sqlite3 rows.
  EXPECT_EQ(packets[0].stamp_ns, 1713492677327771785);
  EXPECT_EQ(packets[75].stamp_ns, 1713492677427229135);
  EXPECT_EQ(packets[76].stamp_ns, 1713492677427865267);
  EXPECT_EQ(packets[228].stamp_ns, 1713492677628080970);
  EXPECT_EQ(packets[303].stamp_ns, 1713492677727441306);
  EXPECT_EQ(packets[378].stamp_ns, 1713492677827134284);
}

TEST(Db3Bag, FolderReadsLikeTheFile) {
  SOCC_REQUIRE_DATA(kVlp32Db3);
  EXPECT_TRUE(isBag(kVlp32Dir));
  EXPECT_TRUE(isBag(kVlp32Db3));
  const std::vector<Packet> a = allPackets(kVlp32Dir);
  const std::vector<Packet> b = allPackets(kVlp32Db3);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].stamp_ns, b[i].stamp_ns);
    EXPECT_EQ(a[i].data, b[i].data);
  }
}

TEST(Db3Bag, Xt32PandarScanPackets) {
  SOCC_REQUIRE_DATA(kXt32Db3);
  std::unique_ptr<BagReader> reader = openBagReader(kXt32Dir);
  ASSERT_EQ(reader->topics().size(), 1u);
  EXPECT_EQ(reader->topics()[0].name, "/pandar_packets");
  EXPECT_EQ(reader->topics()[0].type, "pandar_msgs/msg/PandarScan");
  EXPECT_EQ(reader->topics()[0].messages, 4u);
  const std::vector<Packet> packets = allPackets(kXt32Db3);
  ASSERT_EQ(packets.size(), 4u * 500u);
  std::int64_t previous = 0;
  for (const Packet& p : packets) {
    ASSERT_EQ(p.data.size(), 1080u);
    EXPECT_EQ(p.data[0], 0xEE);
    EXPECT_EQ(p.data[1], 0xFF);
    EXPECT_GE(p.stamp_ns, previous);
    EXPECT_GT(p.stamp_ns, 1673400677802009732 - 200'000'000);
    EXPECT_LT(p.stamp_ns, 1673400678101968885 + 1);
    previous = p.stamp_ns;
  }
}

// The packet path reaches makeDecoder with the options' sensor: the VLP-32C bag decodes into
// sweeps with point times.
TEST(Db3Bag, PacketTopicGoesThroughMakeDecoder) {
  SOCC_REQUIRE_DATA(kVlp32Db3);
  RecordingOptions options;
  options.sensor.model = "vlp32c";
  options.sensor.calibration = kVlp32Dir / "VLP32.yaml";
  std::unique_ptr<ScanStream> stream = openBag(kVlp32Db3, options);
  std::size_t scans = 0;
  while (std::optional<SensorScan> s = stream->next()) {
    ++scans;
    EXPECT_GT(s->size(), 0u);
    EXPECT_EQ(s->time.size(), s->size());
    EXPECT_GT(s->stamp_ns, 1713492677464078412 - 200'000'000);
  }
  EXPECT_GE(scans, 1u);
}

}  // namespace
}  // namespace socc::sensors::bags

namespace socc::sensors::bags {
namespace {

// A split ROS 2 bag: metadata.yaml lists two storage files, read one after the other.
TEST(Db3Bag, SplitBagFolderReadsItsFilesInOrder) {
  SOCC_REQUIRE_DATA(kVlp32Db3);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("socc_test_split_bag_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(kVlp32Db3, dir / "split_0.db3");
  std::filesystem::copy_file(kVlp32Db3, dir / "split_1.db3");
  std::ofstream(dir / "metadata.yaml") << "rosbag2_bagfile_information:\n"
                                          "  version: 5\n"
                                          "  storage_identifier: sqlite3\n"
                                          "  relative_file_paths:\n"
                                          "    - split_0.db3\n"
                                          "    - split_1.db3\n"
                                          "  compression_format: \"\"\n";
  std::unique_ptr<BagReader> reader = openBagReader(dir);
  ASSERT_EQ(reader->topics().size(), 1u);
  EXPECT_EQ(reader->topics()[0].messages, 10u);
  BagPacketSource source(std::move(reader), 0);
  std::size_t packets = 0;
  while (source.next()) ++packets;
  EXPECT_EQ(packets, 2u * 379u);
  std::filesystem::remove_all(dir);
}

// ouster_ros / ouster_sensor_msgs PacketMsg: uint8[] buf, stamped with the bag's receive time.
TEST(PacketMessages, OusterPacketMsgInBothSerializations) {
  const std::vector<std::uint8_t> cdr = {0, 1, 0, 0, 3, 0, 0, 0, 0xAA, 0xBB, 0xCC};
  const std::vector<std::uint8_t> ros1 = {3, 0, 0, 0, 0xAA, 0xBB, 0xCC};
  for (const auto& [bytes, encoding] :
       {std::pair{cdr, Encoding::kCdr}, std::pair{ros1, Encoding::kRos1}}) {
    std::vector<Packet> packets;
    appendPackets(MessageKind::kOusterPacket, ByteView(bytes), encoding, 42, packets);
    ASSERT_EQ(packets.size(), 1u);
    EXPECT_EQ(packets[0].stamp_ns, 42);
    EXPECT_EQ(packets[0].data, (std::vector<std::uint8_t>{0xAA, 0xBB, 0xCC}));
  }
  EXPECT_EQ(messageKind("ouster_sensor_msgs/msg/PacketMsg"), MessageKind::kOusterPacket);
  EXPECT_EQ(messageKind("ouster_ros/PacketMsg"), MessageKind::kOusterPacket);
  EXPECT_EQ(messageKind("sensor_msgs/msg/PointCloud2"), MessageKind::kPointCloud2);
  EXPECT_EQ(messageKind("velodyne_msgs/VelodyneScan"), MessageKind::kVelodyneScan);
  EXPECT_EQ(messageKind("sensor_msgs/msg/Image"), MessageKind::kUnsupported);
}

// Big-endian CDR is decoded; XCDR2 / parameter-list encapsulations are refused, not misread.
TEST(PacketMessages, CdrEncapsulations) {
  const std::vector<std::uint8_t> big = {0, 0, 0, 0, 0, 0, 0, 2, 0x12, 0x34};
  std::vector<Packet> packets;
  appendPackets(MessageKind::kOusterPacket, ByteView(big), Encoding::kCdr, 0, packets);
  ASSERT_EQ(packets.size(), 1u);
  EXPECT_EQ(packets[0].data, (std::vector<std::uint8_t>{0x12, 0x34}));
  const std::vector<std::uint8_t> xcdr2 = {0, 0x11, 0, 0, 2, 0, 0, 0, 0x12, 0x34};
  EXPECT_THROW(
      appendPackets(MessageKind::kOusterPacket, ByteView(xcdr2), Encoding::kCdr, 0, packets),
      FormatError);
}

}  // namespace
}  // namespace socc::sensors::bags
