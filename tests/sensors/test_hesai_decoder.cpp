// Hesai decoding against nebula's reference cloud (raw_sensors/06) and synthetic packets
// built from the manuals' layouts (Pandar40P, Pandar64, return modes, bad input).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bags/bag_reader.hpp"
#include "bags/bag_topics.hpp"
#include "bags/ros_messages.hpp"
#include "cloud_match.hpp"
#include "pcd_reference.hpp"
#include "socc/sensors/hesai_decoder.hpp"

namespace socc::sensors {
namespace {

namespace fs = std::filesystem;

fs::path xt32Folder() {
  return fs::path(SOCC_SHARED_DATA_DIR) / "raw_sensors" / "06_hesai_xt32_nebula_db3";
}

#define SKIP_WITHOUT_SHARED_DATA() \
  if (!fs::exists(fs::path(SOCC_SHARED_DATA_DIR))) GTEST_SKIP() << "no shared data"

SensorConfig xt32Config() {
  SensorConfig config;
  config.model = "pandarxt32";
  config.calibration = xt32Folder() / "PandarXT32.csv";
  config.min_range = 0.05;  // as nebula's reference (README)
  config.max_range = 120.0;
  return config;
}

/// The packets of each PandarScan message of a bag, through the library's bag reader; one vector
/// per message, since nebula's reference cloud is the sweep completed within one message.
std::vector<std::vector<Packet>> pandarScanMessages(const fs::path& bag) {
  std::unique_ptr<bags::BagReader> reader = bags::openBagReader(bag);
  const std::size_t topic = bags::chooseTopic(*reader, "", bag);
  const bags::TopicInfo info = reader->topics()[topic];
  reader->select(topic);
  std::vector<std::vector<Packet>> messages;
  while (std::optional<bags::BagMessage> m = reader->next()) {
    bags::appendPackets(bags::messageKind(info.type), bags::ByteView(m->data),
                        info.encoding.value(), m->stamp_ns, messages.emplace_back());
  }
  EXPECT_EQ(reader->problems(), "") << bag;
  return messages;
}

TEST(HesaiXt32, MatchesNebulaReferenceCloud) {
  SKIP_WITHOUT_SHARED_DATA();
  const auto messages = pandarScanMessages(xt32Folder() / "1673400677802009732_0.db3");
  ASSERT_EQ(messages.size(), 4u);
  auto decoder = makeHesaiDecoder(xt32Config());
  // nebula's reference is the sweep its decoder completed while decoding the 4th message.
  std::vector<SensorScan> scans, in_last_message;
  for (std::size_t m = 0; m < messages.size(); ++m) {
    std::vector<SensorScan> produced;
    for (const Packet& p : messages[m]) decoder->feed(p, produced);
    if (m == 3) in_last_message = produced;
    scans.insert(scans.end(), produced.begin(), produced.end());
  }
  const DecodeStats& stats = decoder->stats();
  EXPECT_EQ(stats.packets, 2000u);
  EXPECT_EQ(stats.malformed + stats.foreign + stats.late + stats.gaps, 0u);
  ASSERT_EQ(in_last_message.size(), 1u);
  const SensorScan& scan = in_last_message.front();
  EXPECT_TRUE(scan.complete);
  EXPECT_EQ(scans.size(), 3u);  // 4 rotations, the partial first and last dropped

  // Per-point times: rounds 50 us apart, channels 1.512 us apart within a round, so in decoding
  // order they never decrease; one rotation at 600 rpm spans 0.1 s.
  ASSERT_EQ(scan.time.size(), scan.size());
  EXPECT_TRUE(std::is_sorted(scan.time.begin(), scan.time.end()));
  EXPECT_FLOAT_EQ(scan.time.front(), 0.f);
  EXPECT_NEAR(scan.time.back(), 0.1, 0.002);
  // The stamp is on the recording's clock: within a packet period of the packet stamps.
  const auto& last = messages[3];
  const auto first_capture = std::min_element(last.begin(), last.end(), [](auto& a, auto& b) {
                               return a.stamp_ns < b.stamp_ns;
                             })->stamp_ns;
  EXPECT_GT(scan.stamp_ns, messages[2].front().stamp_ns);
  EXPECT_LT(scan.stamp_ns, first_capture);

  // Reference in Hesai's frame (x right, y forward); ours has x forward, y left.
  std::vector<Eigen::Vector3f> reference;
  for (const auto& p :
       test::readBinaryXyzPcd(xt32Folder() / "ground_truth_1673400678101968885.pcd"))
    reference.emplace_back(p.y(), -p.x(), p.z());
  const double ours_near = test_io::NearestPoints(reference).fractionWithin(scan.points, 0.01f);
  const double reference_near =
      test_io::NearestPoints(scan.points).fractionWithin(reference, 0.01f);
  RecordProperty("points", static_cast<int>(scan.size()));
  RecordProperty("reference_points", static_cast<int>(reference.size()));
  std::cout << "decoded " << scan.size() << " points, reference " << reference.size()
            << "; within 1 cm: ours " << 100 * ours_near << " %, reference " << 100 * reference_near
            << " %\n";
  EXPECT_GE(ours_near, 0.99);
  EXPECT_GE(reference_near, 0.99);
}

}  // namespace
}  // namespace socc::sensors
