// Bags written by independent tools from two real KITTI scans (writers/write_bag_fixtures.sh,
// the ctest fixture sensors.bag_writers): ROS 1 bags by Debian's python3-rosbag (chunks none,
// bz2, lz4) and MCAP files by @mcap/core with Foxglove's CDR and ROS 1 serializers (chunks
// none, zstd, lz4). Every coordinate and intensity reads back bit-identical; stamps and point
// times as written; topic choice and its errors; sensor_msgs/Imu samples as written; the
// static transforms of /tf_static.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>
#include <zstd.h>

#include <cmath>
#include <cstring>

#include "bag_test_data.hpp"
#include "bags/bag_reader.hpp"
#include "socc/kitti_io.hpp"
#include "socc/sensors/bag_recording.hpp"
#include "socc/sensors/imu_stream.hpp"
#include "socc/sensors/static_transforms.hpp"

namespace socc::sensors::bags {
namespace {

const std::filesystem::path kFixtures = SOCC_BAG_FIXTURES_DIR;
constexpr std::int64_t kStamp0 = 1'700'000'000'000'000'500;  // scan 0's header stamp [ns]

struct KittiScan {
  std::vector<Eigen::Vector3f> points;  // as stored, minus the (0, 0, 0) no-returns
  std::vector<float> intensity;
  std::vector<std::size_t> index;  // each kept point's index in the file
};

KittiScan kittiScan(int i) {
  const std::filesystem::path bin =
      test::sharedData() / "kitti_00_first16" / "velodyne" / (i == 0 ? "000000.bin" : "000001.bin");
  std::vector<float> reflectance;
  const socc::Points points = readKittiBin(bin, &reflectance);
  KittiScan s;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (points[k].isZero() || !points[k].allFinite()) continue;
    s.points.push_back(points[k]);
    s.intensity.push_back(reflectance[k]);
    s.index.push_back(k);
  }
  return s;
}

bool bitIdentical(const std::vector<Eigen::Vector3f>& a, const std::vector<Eigen::Vector3f>& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(Eigen::Vector3f)) == 0;
}
bool bitIdentical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::vector<SensorScan> readAll(const std::filesystem::path& bag, const std::string& topic) {
  RecordingOptions options;
  options.topic = topic;
  std::unique_ptr<ScanStream> stream = openBag(bag, options);
  std::vector<SensorScan> scans;
  while (std::optional<SensorScan> s = stream->next()) scans.push_back(std::move(*s));
  EXPECT_EQ(stream->problems(), "") << bag;
  return scans;
}

class IndependentWriter : public testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
    file_ = kFixtures / GetParam();
    ASSERT_TRUE(std::filesystem::exists(file_))
        << file_ << " missing: run the fixture first (ctest -R 'sensors\\.|Independent')";
  }
  bool isMcap() const { return file_.extension() == ".mcap"; }
  std::filesystem::path file_;
};

// x y z intensity float32, the KITTI layout: every value as in the .bin file.
TEST_P(IndependentWriter, Float32CloudsReadBackBitIdentical) {
  const std::vector<SensorScan> scans = readAll(file_, "/points");
  ASSERT_EQ(scans.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const KittiScan expected = kittiScan(i);
    const SensorScan& s = scans[static_cast<std::size_t>(i)];
    EXPECT_GT(s.size(), 100000u);
    EXPECT_TRUE(bitIdentical(s.points, expected.points)) << "scan " << i;
    EXPECT_TRUE(bitIdentical(s.intensity, expected.intensity)) << "scan " << i;
    EXPECT_TRUE(s.time.empty());
    EXPECT_EQ(s.stamp_ns, kStamp0 + i * 1'000'000'000LL);
    EXPECT_EQ(s.seq, i);
    EXPECT_NE(s.source.find("/points"), std::string::npos);
  }
}

// x y z float64, intensity float32 and a time field: the ROS 1 bags' "timestamp" in absolute
// float64 seconds, the MCAP's ROS 1-encoded "time" in float32 seconds relative to the header;
// both = header stamp + point index * 1 us.
TEST_P(IndependentWriter, Float64CloudsWithTimesReadBack) {
  const std::vector<SensorScan> scans = readAll(file_, isMcap() ? "/points_ros1" : "/points_f64");
  ASSERT_EQ(scans.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const KittiScan expected = kittiScan(i);
    const SensorScan& s = scans[static_cast<std::size_t>(i)];
    EXPECT_TRUE(bitIdentical(s.points, expected.points)) << "scan " << i;
    EXPECT_TRUE(bitIdentical(s.intensity, expected.intensity)) << "scan " << i;
    ASSERT_EQ(s.time.size(), s.size());
    const double first_s = static_cast<double>(expected.index[0]) * 1e-6;
    EXPECT_NEAR(static_cast<double>(s.stamp_ns - (kStamp0 + i * 1'000'000'000LL)), first_s * 1e9,
                isMcap() ? 1.0 : 300.0);
    for (std::size_t k = 0; k < s.size(); k += 997) {
      const double want = static_cast<double>(expected.index[k] - expected.index[0]) * 1e-6;
      // float64 epoch seconds resolve 0.24 us; float32 relative seconds far better.
      ASSERT_NEAR(s.time[k], want, isMcap() ? 1e-7 : 3e-7) << "scan " << i << " point " << k;
    }
  }
}

TEST_P(IndependentWriter, TopicsAndTopicChoice) {
  const std::unique_ptr<BagReader> reader = openBagReader(file_);
  ASSERT_EQ(reader->topics().size(), 5u);
  for (const TopicInfo& t : reader->topics())
    EXPECT_EQ(t.messages, t.name == "/imu" ? 21u : t.name == "/tf_static" ? 1u : 2u) << t.name;
  EXPECT_TRUE(isBag(file_));
  // Two PointCloud2 topics: the caller must choose; the error lists the topics.
  try {
    openBag(file_, RecordingOptions{});
    FAIL() << "no error without a topic";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("several LiDAR topics"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/chatter"), std::string::npos) << e.what();
  }
  RecordingOptions chatter;
  chatter.topic = "/chatter";
  try {
    openBag(file_, chatter);
    FAIL() << "no error for a String topic";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("std_msgs"), std::string::npos) << e.what();
  }
  RecordingOptions absent;
  absent.topic = "/nope";
  EXPECT_THROW(openBag(file_, absent), std::runtime_error);
}

// /imu: sensor_msgs/Imu as the writers' imu_sample(k) makes it (write_ros1_bags.py), the
// orientation dropped where the covariance says there is none; never taken for a LiDAR topic.
TEST_P(IndependentWriter, ImuSamplesReadBackAsWritten) {
  const std::unique_ptr<ImuStream> imu = openImuTopic(file_, "");  // the only Imu topic
  std::vector<ImuSample> samples;
  while (std::optional<ImuSample> s = imu->next()) samples.push_back(std::move(*s));
  EXPECT_EQ(imu->problems(), "");
  ASSERT_EQ(samples.size(), 21u);
  for (int k = 0; k < 21; ++k) {
    const ImuSample& s = samples[static_cast<std::size_t>(k)];
    EXPECT_EQ(s.stamp_ns, 1'699'999'999'500'000'000 + k * 100'000'000LL) << k;
    ASSERT_EQ(s.orientation.has_value(), k != 5) << k;
    if (s.orientation) {
      EXPECT_DOUBLE_EQ(s.orientation->x(), std::sin(0.005 * k)) << k;
      EXPECT_DOUBLE_EQ(s.orientation->w(), std::cos(0.005 * k)) << k;
      EXPECT_EQ(s.orientation->y(), 0.0);
      EXPECT_EQ(s.orientation->z(), 0.0);
    }
    EXPECT_EQ(s.orientation_covariance(0, 0), k == 5 ? -1.0 : 1e-4) << k;
    EXPECT_EQ(s.orientation_covariance(1, 1), 4e-4);
    EXPECT_EQ(s.orientation_covariance(2, 2), 1e-2);
    EXPECT_EQ(s.angular_velocity, Eigen::Vector3d(0.1, 0.2, 0.3 + k)) << k;
    EXPECT_EQ(s.linear_acceleration, Eigen::Vector3d(0.5, -0.25, 9.81));
  }
  try {
    openImuTopic(file_, "/points");
    FAIL() << "a PointCloud2 topic taken for an IMU";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no sensor_msgs/Imu topic /points"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("/imu"), std::string::npos) << e.what();  // listed
  }
}

// /tf_static: base_link -> velodyne (ROS 1: "/base_link") and base_link -> imu, joined into the
// IMU's mounting in the frame the scans name.
TEST_P(IndependentWriter, StaticTransformsJoinTheScansFrameToTheImus) {
  const StaticTransforms mounts = StaticTransforms::fromBag(file_);
  const std::optional<Eigen::Isometry3d> lidar_T_imu = mounts.lookup("velodyne", "imu");
  ASSERT_TRUE(lidar_T_imu) << mounts.describe();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  EXPECT_LT((lidar_T_imu->linear() - turn).norm(), 1e-12);
  EXPECT_LT((lidar_T_imu->translation() - Eigen::Vector3d(0.1, 0.0, -1.2)).norm(), 1e-12);
  EXPECT_FALSE(mounts.lookup("velodyne", "camera"));
  EXPECT_EQ(readAll(file_, "/points").at(0).frame_id, "velodyne");
}

INSTANTIATE_TEST_SUITE_P(Bags, IndependentWriter,
                         testing::Values("clouds_none.bag", "clouds_bz2.bag", "clouds_lz4.bag",
                                         "clouds_none.mcap", "clouds_zstd.mcap", "clouds_lz4.mcap"),
                         [](const testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// A ROS 2 .db3 bag of PointCloud2: the tables as rosbag2's sqlite3 storage creates them, holding
// the CDR messages @mcap/core's serializer wrote into clouds_none.mcap, as they are and (param
// true) each compressed to a zstd frame as rosbag2's compression_mode "message" stores them.
class IndependentCdrInDb3 : public testing::TestWithParam<bool> {};

TEST_P(IndependentCdrInDb3, PointCloudsReadBackBitIdentical) {
  SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
  const std::filesystem::path mcap = kFixtures / "clouds_none.mcap";
  ASSERT_TRUE(std::filesystem::exists(mcap)) << mcap << " missing: run sensors.bag_writers";
  const std::filesystem::path db3 = std::filesystem::temp_directory_path() /
                                    ("socc_test_clouds_" + std::to_string(::getpid()) + ".db3");
  std::filesystem::remove(db3);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db3.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db,
                   "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT "
                   "NOT NULL, serialization_format TEXT NOT NULL, offered_qos_profiles TEXT "
                   "NOT NULL);"
                   "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
                   "timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
                   "INSERT INTO topics VALUES (1, '/points', 'sensor_msgs/msg/PointCloud2', "
                   "'cdr', '');",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  std::unique_ptr<BagReader> reader = openBagReader(mcap);
  reader->select(0);
  ASSERT_EQ(reader->topics()[0].name, "/points");
  while (const std::optional<BagMessage> m = reader->next()) {
    sqlite3_stmt* insert = nullptr;
    sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (1, ?, ?)", -1,
                       &insert, nullptr);
    sqlite3_bind_int64(insert, 1, m->stamp_ns);
    std::vector<std::uint8_t> blob = m->data;
    if (GetParam()) {
      blob.resize(ZSTD_compressBound(m->data.size()));
      blob.resize(ZSTD_compress(blob.data(), blob.size(), m->data.data(), m->data.size(), 1));
    }
    sqlite3_bind_blob(insert, 2, blob.data(), static_cast<int>(blob.size()), SQLITE_STATIC);
    EXPECT_EQ(sqlite3_step(insert), SQLITE_DONE);
    sqlite3_finalize(insert);
  }
  sqlite3_close(db);
  const std::vector<SensorScan> scans = readAll(db3, "");
  std::filesystem::remove(db3);
  ASSERT_EQ(scans.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const KittiScan expected = kittiScan(i);
    const SensorScan& s = scans[static_cast<std::size_t>(i)];
    EXPECT_TRUE(bitIdentical(s.points, expected.points)) << "scan " << i;
    EXPECT_TRUE(bitIdentical(s.intensity, expected.intensity)) << "scan " << i;
    EXPECT_EQ(s.stamp_ns, kStamp0 + i * 1'000'000'000LL);
  }
}

INSTANTIATE_TEST_SUITE_P(Db3, IndependentCdrInDb3, testing::Values(false, true));

}  // namespace
}  // namespace socc::sensors::bags
