// Damaged input: truncated and corrupted bags, MCAPs and .db3 files, truncated messages. A
// reader throws std::runtime_error or reports the damage; it never crashes, and every scan it
// yields is one that was written (bit-identical), never one with garbage points.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iostream>

#include "bag_test_data.hpp"
#include "bags/bag_packet_source.hpp"
#include "bags/bag_reader.hpp"
#include "bags/pointcloud2_scan.hpp"
#include "socc/kitti_io.hpp"
#include "socc/sensors/bag_recording.hpp"

namespace socc::sensors::bags {
namespace {

namespace fs = std::filesystem;

const fs::path kFixtureDir = SOCC_BAG_FIXTURES_DIR;

std::vector<std::uint8_t> fileBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

/// A damaged copy of a fixture in the temporary folder (same extension), removed again.
class DamagedCopy {
 public:
  DamagedCopy(const std::vector<std::uint8_t>& bytes, const fs::path& like, const std::string& tag)
      : path_(fs::temp_directory_path() / ("socc_test_bad_bags_" + std::to_string(::getpid()) +
                                           "_" + tag + like.extension().string())) {
    std::ofstream(path_, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  }
  ~DamagedCopy() {
    std::error_code ignored;
    fs::remove(path_, ignored);
  }
  DamagedCopy(const DamagedCopy&) = delete;
  DamagedCopy& operator=(const DamagedCopy&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The scans written into the fixtures' /points topic (KITTI 000000 and 000001, no zeros).
const std::vector<std::vector<Eigen::Vector3f>>& writtenScans() {
  static const std::vector<std::vector<Eigen::Vector3f>> scans = [] {
    std::vector<std::vector<Eigen::Vector3f>> s;
    for (const char* name : {"000000.bin", "000001.bin"}) {
      std::vector<Eigen::Vector3f> kept;
      for (const Eigen::Vector3f& p :
           readKittiBin(test::sharedData() / "kitti_00_first16" / "velodyne" / name)) {
        if (!p.isZero()) kept.push_back(p);
      }
      s.push_back(std::move(kept));
    }
    return s;
  }();
  return scans;
}

bool isWritten(const SensorScan& scan) {
  for (const auto& w : writtenScans()) {
    if (w.size() == scan.size() &&
        std::memcmp(w.data(), scan.points.data(), w.size() * sizeof(Eigen::Vector3f)) == 0) {
      return true;
    }
  }
  return false;
}

/// Reads /points of a damaged file to the end. Returns the number of scans; every scan must be
/// one that was written. reported: whether the damage was told (exception or problems()).
std::size_t readDamaged(const fs::path& file, bool& reported) {
  reported = false;
  RecordingOptions options;
  options.topic = "/points";
  std::size_t scans = 0;
  try {
    std::unique_ptr<ScanStream> stream = openBag(file, options);
    while (std::optional<SensorScan> s = stream->next()) {
      EXPECT_TRUE(isWritten(*s)) << file << ": scan " << scans << " was never written";
      ++scans;
    }
    reported = !stream->problems().empty();
  } catch (const std::runtime_error&) {
    reported = true;
  }
  return scans;
}

class DamagedBag : public testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
    file_ = kFixtureDir / GetParam();
    ASSERT_TRUE(fs::exists(file_)) << file_ << " missing: run the fixture sensors.bag_writers";
    bytes_ = fileBytes(file_);
  }
  fs::path file_;
  std::vector<std::uint8_t> bytes_;
};

// A cut anywhere: the scans before the cut come out whole, the loss is reported.
TEST_P(DamagedBag, TruncatedFilesYieldOnlyWrittenScansAndReportTheLoss) {
  for (const double fraction : {0.0, 0.0005, 0.3, 0.6, 0.999}) {
    std::vector<std::uint8_t> cut(
        bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(
                                             fraction * static_cast<double>(bytes_.size())));
    bool reported = false;
    const std::size_t scans = readDamaged(DamagedCopy(cut, file_, "cut").path(), reported);
    EXPECT_LE(scans, 2u);
    EXPECT_TRUE(reported) << "cut at " << fraction << ": " << scans << " scans, nothing reported";
  }
}

// Bytes flipped in headers, chunks and the index: chunks fail their checks (MCAP CRC, lz4
// content checksum) and are skipped, or the file is refused; a scan that comes out is exact.
TEST_P(DamagedBag, CorruptedFilesYieldOnlyWrittenScans) {
  for (const double fraction : {0.0001, 0.002, 0.2, 0.55, 0.9, 0.9995}) {
    std::vector<std::uint8_t> bad = bytes_;
    bad[static_cast<std::size_t>(fraction * static_cast<double>(bad.size()))] ^= 0x5A;
    bool reported = false;
    const std::size_t scans = readDamaged(DamagedCopy(bad, file_, "flip").path(), reported);
    if (scans < 2) {
      EXPECT_TRUE(reported) << "flip at " << fraction << ": a scan lost silently";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Bags, DamagedBag, testing::Values("clouds_lz4.bag", "clouds_zstd.mcap"),
                         [](const testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

/// The offset of the data length of the first message record (op 0x02) of an uncompressed ROS 1
/// bag: the header whose fields (uint32 length + "name=value") hold "op=\x02" and add up to the
/// uint32 header length before them.
std::size_t firstMessageDataLength(const std::vector<std::uint8_t>& bytes) {
  const std::string op("\x04\0\0\0op=\x02", 8);
  const auto at = std::search(bytes.begin(), bytes.end(), op.begin(), op.end());
  const auto pos = static_cast<std::size_t>(at - bytes.begin());
  const auto u32 = [&](std::size_t i) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + i, 4);
    return v;
  };
  for (std::size_t start = pos; start >= 4 && start + 256 > pos; --start) {
    const std::size_t end = start + u32(start - 4);
    std::size_t i = start;
    while (i + 4 <= end && i + 4 + u32(i) <= end) i += 4 + u32(i);
    if (i == end && end > pos && end + 4 <= bytes.size()) return end;
  }
  return 0;
}

// A message length past its chunk makes rosbag_storage read past its buffer (it trusts the
// length; ASan: heap-buffer-overflow in Bag::readMessageDataIntoStream). The read runs in a
// child process: whatever happens there, this process goes on and yields only whole scans.
// (Under ASan the child prints rosbag_storage's heap-buffer-overflow report and aborts: expected.)
TEST(DamagedRos1Bag, MessageLengthPastItsChunkNeverCrashesTheReader) {
  SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
  const fs::path file = kFixtureDir / "clouds_none.bag";
  ASSERT_TRUE(fs::exists(file)) << file << " missing: run the fixture sensors.bag_writers";
  const std::vector<std::uint8_t> bytes = fileBytes(file);
  const std::size_t length_at = firstMessageDataLength(bytes);
  ASSERT_GT(length_at, 0u) << "no message record found";
  for (const std::uint32_t length : {0x01000000u, 0x7FFFFFF0u}) {
    std::vector<std::uint8_t> bad = bytes;
    std::memcpy(bad.data() + length_at, &length, 4);
    const DamagedCopy copy(bad, file, "length");
    bool reported = false;
    const std::size_t scans = readDamaged(copy.path(), reported);
    EXPECT_LE(scans, 2u);
    // All topics: what the reader reports (printed for docs/sensors_bags.md).
    std::unique_ptr<BagReader> reader = openBagReader(copy.path());
    std::size_t messages = 0;
    while (reader->next()) ++messages;
    std::cout << "length " << length << ": " << scans << " scans, " << messages
              << " messages of 6; " << reader->problems();
    if (scans < 2) {
      EXPECT_TRUE(reported) << "length " << length << ": a scan lost silently";
    }
  }
}

// A cut or an unindexed bag is refused with the reason (rosbag_storage reads the index only).
TEST(DamagedRos1Bag, TruncatedBagIsRefusedWithTheReason) {
  SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
  const fs::path file = kFixtureDir / "clouds_lz4.bag";
  ASSERT_TRUE(fs::exists(file)) << file << " missing: run the fixture sensors.bag_writers";
  std::vector<std::uint8_t> cut = fileBytes(file);
  cut.resize(cut.size() / 2);
  try {
    openBagReader(DamagedCopy(cut, file, "half").path());
    FAIL() << "a truncated bag was opened";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not a readable ROS 1 bag"), std::string::npos) << what;
  }
}

const fs::path kDamagedDb3Source =
    test::rawSensors() / "03_velodyne_vlp32c_nebula_db3" / "1713492677464078412_0.db3";

// SQLite reports a cut or damaged database; the packets that come out are whole.
TEST(DamagedDb3, TruncatedAndCorruptedDatabases) {
  SOCC_REQUIRE_DATA(kDamagedDb3Source);
  const std::vector<std::uint8_t> bytes = fileBytes(kDamagedDb3Source);
  for (const double fraction : {0.0, 0.01, 0.5, 0.9}) {
    std::vector<std::uint8_t> cut(
        bytes.begin(),
        bytes.begin() + static_cast<std::ptrdiff_t>(fraction * static_cast<double>(bytes.size())));
    std::vector<std::uint8_t> flipped = bytes;
    flipped[static_cast<std::size_t>(fraction * static_cast<double>(bytes.size()))] ^= 0xFF;
    for (const auto& [damaged, tag] : {std::pair{cut, "cut"}, std::pair{flipped, "flip"}}) {
      std::size_t packets = 0;
      try {
        const DamagedCopy copy(damaged, kDamagedDb3Source, tag);
        BagPacketSource source(openBagReader(copy.path()), 0);
        while (std::optional<Packet> p = source.next()) {
          EXPECT_EQ(p->data.size(), 1206u);
          ++packets;
        }
        if (packets < 379) {
          EXPECT_NE(source.problems(), "") << tag << " " << fraction;
        }
      } catch (const std::exception& e) {
        SUCCEED() << e.what();
      }
    }
  }
}

TEST(DamagedDb3, NotABag) {
  EXPECT_THROW(openBagReader(DamagedCopy({'h', 'e', 'l', 'l', 'o'}, "x.db3", "text").path()),
               std::runtime_error);
  EXPECT_THROW(openBagReader(DamagedCopy({}, "x.mcap", "empty").path()), std::runtime_error);
  EXPECT_THROW(openBagReader(DamagedCopy({}, "x.bag", "empty").path()), std::runtime_error);
  EXPECT_THROW(openBagReader("/nonexistent/x.bag"), std::runtime_error);
  EXPECT_THROW(openBagReader(DamagedCopy({1, 2, 3}, "x.txt", "other").path()), std::runtime_error);
}

// A record length that wraps the file offset around (found by fuzz_bag_containers: the
// channel scan of an MCAP without summary looped for ever): opening returns, reading stops.
TEST(DamagedMcap, RecordLengthWrappingTheOffsetEndsTheReading) {
  std::vector<std::uint8_t> bytes = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n', 0x01};
  for (int i = 0; i < 8; ++i) bytes.push_back(0xFF);  // length 2^64 - 1
  bytes[9] = 0xF7;                                    // 2^64 - 9: offset + 9 + length wraps
  const DamagedCopy copy(bytes, "x.mcap", "wrap");
  std::unique_ptr<BagReader> reader = openBagReader(copy.path());
  EXPECT_FALSE(reader->next());
  EXPECT_NE(reader->problems().find("reading stopped"), std::string::npos) << reader->problems();
}

// Every prefix of a real serialized message fails to parse (FormatError), never reads past it;
// a VelodyneScan cut inside a packet yields no packet at all.
TEST(MalformedMessages, TruncatedMessagesThrowFormatError) {
  SOCC_REQUIRE_DATA(kDamagedDb3Source);
  std::unique_ptr<BagReader> reader = openBagReader(kDamagedDb3Source);
  const std::optional<BagMessage> m = reader->next();
  ASSERT_TRUE(m);
  for (std::size_t n = 0; n < m->data.size(); n += 997) {
    std::vector<Packet> packets;
    EXPECT_THROW(appendPackets(MessageKind::kVelodyneScan, ByteView(m->data.data(), n),
                               Encoding::kCdr, 0, packets),
                 FormatError);
    EXPECT_TRUE(packets.empty());
    EXPECT_THROW(parsePointCloud2(ByteView(m->data.data(), n), Encoding::kCdr), FormatError);
    EXPECT_THROW(parsePointCloud2(ByteView(m->data.data(), n), Encoding::kRos1), FormatError);
  }
}

TEST(MalformedMessages, PointCloudWithWrongSizesIsDroppedAndCounted) {
  SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
  const fs::path mcap = kFixtureDir / "clouds_zstd.mcap";
  ASSERT_TRUE(fs::exists(mcap));
  std::unique_ptr<BagReader> reader = openBagReader(mcap);
  reader->select(0);
  std::optional<BagMessage> m = reader->next();
  ASSERT_TRUE(m);
  PointCloud2Msg cloud = parsePointCloud2(ByteView(m->data), Encoding::kCdr);
  cloud.width += 1;  // one point more than the data holds
  EXPECT_THROW(convertPointCloud2(cloud, 0), FormatError);
  cloud.width -= 1;
  cloud.point_step = 8;  // z and intensity past the point
  EXPECT_THROW(convertPointCloud2(cloud, 0), FormatError);
}

}  // namespace
}  // namespace socc::sensors::bags
