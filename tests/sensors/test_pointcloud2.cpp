// PointCloud2 -> SensorScan on clouds built field by field: coordinate types, byte order,
// row padding, dropped points, intensity / ring fields and the rules for point times.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "bags/pointcloud2_scan.hpp"

namespace socc::sensors::bags {
namespace {

constexpr std::int64_t kHeaderNs = 1'700'000'000'123'456'789;

/// A cloud whose points are written value by value at given offsets (little-endian unless
/// big_endian: then each value's bytes are reversed).
class CloudBuilder {
 public:
  CloudBuilder(std::uint32_t point_step, bool big_endian = false) {
    cloud_.point_step = point_step;
    cloud_.is_bigendian = big_endian;
    cloud_.height = 1;
    cloud_.header.stamp_ns = kHeaderNs;
  }
  CloudBuilder& field(const std::string& name, std::uint32_t offset, std::uint8_t type) {
    cloud_.fields.push_back({name, offset, type, 1});
    return *this;
  }
  template <class T>
  CloudBuilder& set(std::size_t point, std::uint32_t offset, T value) {
    const std::size_t at = point * cloud_.point_step + offset;
    if (bytes_.size() < (point + 1) * cloud_.point_step)
      bytes_.resize((point + 1) * cloud_.point_step);
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (cloud_.is_bigendian) std::reverse(b, b + sizeof(T));
    std::memcpy(bytes_.data() + at, b, sizeof(T));
    return *this;
  }
  PointCloud2Msg build() {
    cloud_.width = static_cast<std::uint32_t>(bytes_.size() / cloud_.point_step);
    cloud_.row_step = cloud_.width * cloud_.point_step;
    cloud_.data = ByteView(bytes_);
    return cloud_;
  }

 private:
  PointCloud2Msg cloud_;
  std::vector<std::uint8_t> bytes_;
};

/// x, y, z, intensity float32 (the KITTI / velodyne layout) plus a time field at 16.
CloudBuilder xyzi(std::uint32_t point_step = 16) {
  CloudBuilder b(point_step);
  b.field("x", 0, 7).field("y", 4, 7).field("z", 8, 7).field("intensity", 12, 7);
  return b;
}

TEST(PointCloud2, Float32PointsAndIntensityExactlyNanAndZeroDropped) {
  CloudBuilder b = xyzi();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  b.set(0, 0, 1.25f).set(0, 4, -2.5f).set(0, 8, 0.1f).set(0, 12, 17.f);
  b.set(1, 0, nan).set(1, 4, 1.f).set(1, 8, 1.f);                                     // dropped
  b.set(2, 0, 0.f).set(2, 4, 0.f).set(2, 8, 0.f);                                     // dropped
  b.set(3, 0, 3.f).set(3, 4, std::numeric_limits<float>::infinity()).set(3, 8, 1.f);  // dropped
  b.set(4, 0, 1e-30f).set(4, 4, 4.f).set(4, 8, -7.f).set(4, 12, 255.f);
  const PointCloud2Conversion c = convertPointCloud2(b.build(), 5);
  EXPECT_EQ(c.dropped_points, 3u);
  ASSERT_EQ(c.scan.size(), 2u);
  EXPECT_EQ(c.scan.points[0], Eigen::Vector3f(1.25f, -2.5f, 0.1f));
  EXPECT_EQ(c.scan.points[1], Eigen::Vector3f(1e-30f, 4.f, -7.f));
  EXPECT_EQ(c.scan.intensity, (std::vector<float>{17.f, 255.f}));
  EXPECT_TRUE(c.scan.time.empty());
  EXPECT_TRUE(c.scan.ring.empty());
  EXPECT_EQ(c.scan.stamp_ns, kHeaderNs);
}

TEST(PointCloud2, Float64BigEndianReflectivityRingAndRowPadding) {
  CloudBuilder b(40, /*big_endian=*/true);
  b.field("x", 0, 8)
      .field("y", 8, 8)
      .field("z", 16, 8)
      .field("reflectivity", 24, 4)
      .field("ring", 26, 4)
      .field("ambient", 28, 6);
  b.set(0, 0, 1.5)
      .set(0, 8, 2.0)
      .set(0, 16, -3.0)
      .set(0, 24, std::uint16_t{300})
      .set(0, 26, std::uint16_t{31});
  b.set(1, 0, 4.0)
      .set(1, 8, 5.0)
      .set(1, 16, 6.0)
      .set(1, 24, std::uint16_t{7})
      .set(1, 26, std::uint16_t{0});
  PointCloud2Msg cloud = b.build();
  // The same two points as 2 rows of 1 with 8 padding bytes after each row.
  std::vector<std::uint8_t> padded(cloud.data.data, cloud.data.data + 40);
  padded.resize(48);
  padded.insert(padded.end(), cloud.data.data + 40, cloud.data.data + 80);
  cloud.height = 2;
  cloud.width = 1;
  cloud.row_step = 48;
  cloud.data = ByteView(padded);
  const PointCloud2Conversion c = convertPointCloud2(cloud, 0);
  ASSERT_EQ(c.scan.size(), 2u);
  EXPECT_EQ(c.scan.points[0], Eigen::Vector3f(1.5f, 2.f, -3.f));
  EXPECT_EQ(c.scan.points[1], Eigen::Vector3f(4.f, 5.f, 6.f));
  EXPECT_EQ(c.scan.intensity, (std::vector<float>{300.f, 7.f}));
  EXPECT_EQ(c.scan.ring, (std::vector<std::uint16_t>{31, 0}));
}

// velodyne_pointcloud: float32 "time" in s relative to the header stamp (may be negative).
TEST(PointCloud2, Float32RelativeSeconds) {
  CloudBuilder b = xyzi(20);
  b.field("time", 16, 7);
  b.set(0, 0, 1.f)
      .set(0, 16, -0.05f)
      .set(1, 0, 2.f)
      .set(1, 16, 0.f)
      .set(2, 0, 3.f)
      .set(2, 16, 0.03f);
  const PointCloud2Conversion c = convertPointCloud2(b.build(), 0);
  EXPECT_EQ(c.time_field, "time");
  EXPECT_EQ(c.scan.stamp_ns, kHeaderNs + std::llround(double{-0.05f} * 1e9));
  ASSERT_EQ(c.scan.time.size(), 3u);
  EXPECT_FLOAT_EQ(c.scan.time[0], 0.f);
  EXPECT_NEAR(c.scan.time[1], 0.05, 1e-8);
  EXPECT_NEAR(c.scan.time[2], 0.08, 1e-8);
}

// Ouster: uint32 "t" in ns relative to the header stamp; times start where the earliest is.
TEST(PointCloud2, Uint32RelativeNanoseconds) {
  CloudBuilder b = xyzi(20);
  b.field("t", 16, 6);
  b.set(0, 0, 1.f)
      .set(0, 16, std::uint32_t{2'000'000})
      .set(1, 0, 2.f)
      .set(1, 16, std::uint32_t{99'000'000});
  const PointCloud2Conversion c = convertPointCloud2(b.build(), 0);
  EXPECT_EQ(c.scan.stamp_ns, kHeaderNs + 2'000'000);
  EXPECT_EQ(c.scan.time, (std::vector<float>{0.f, 0.097f}));
}

// Integer times spanning 1e3..1e6 units are microseconds (in ns the sweep would last < 1 ms).
TEST(PointCloud2, IntegerSpanDecidesMicroseconds) {
  CloudBuilder b = xyzi(20);
  b.field("offset_time", 16, 6);
  b.set(0, 0, 1.f).set(0, 16, std::uint32_t{0}).set(1, 0, 2.f).set(1, 16, std::uint32_t{100'000});
  const PointCloud2Conversion c = convertPointCloud2(b.build(), 0);
  EXPECT_EQ(c.scan.stamp_ns, kHeaderNs);
  EXPECT_EQ(c.scan.time, (std::vector<float>{0.f, 0.1f}));
}

// Hesai (pandar_pointcloud): float64 "timestamp" in absolute seconds; the header is ignored.
TEST(PointCloud2, Float64AbsoluteSeconds) {
  CloudBuilder b = xyzi(24);
  b.field("timestamp", 16, 8);
  b.set(0, 0, 1.f).set(0, 16, 1673400677.850).set(1, 0, 2.f).set(1, 16, 1673400677.800);
  const PointCloud2Conversion c = convertPointCloud2(b.build(), 0);
  EXPECT_NEAR(static_cast<double>(c.scan.stamp_ns - 1'673'400'677'800'000'000), 0.0, 1000.0);
  ASSERT_EQ(c.scan.time.size(), 2u);
  EXPECT_NEAR(c.scan.time[0], 0.05, 1e-6);
  EXPECT_EQ(c.scan.time[1], 0.f);
}

TEST(PointCloud2, UnusableTimesAreReportedNotGuessed) {
  CloudBuilder coarse = xyzi(20);  // float32 cannot hold epoch seconds to a sweep's precision
  coarse.field("timestamp", 16, 7);
  coarse.set(0, 0, 1.f).set(0, 16, 1.7e9f);
  PointCloud2Conversion c = convertPointCloud2(coarse.build(), 0);
  EXPECT_TRUE(c.scan.time.empty());
  EXPECT_NE(c.time_problem.find("float32"), std::string::npos) << c.time_problem;
  EXPECT_EQ(c.scan.stamp_ns, kHeaderNs);

  CloudBuilder longer = xyzi(20);  // 5 s is not one sweep
  longer.field("time", 16, 7);
  longer.set(0, 0, 1.f).set(0, 16, 0.f).set(1, 0, 1.f).set(1, 16, 5.f);
  c = convertPointCloud2(longer.build(), 0);
  EXPECT_TRUE(c.scan.time.empty());
  EXPECT_NE(c.time_problem.find("span"), std::string::npos) << c.time_problem;
  EXPECT_EQ(c.scan.size(), 2u);
}

TEST(PointCloud2, HeaderStampZeroFallsBackToTheReceiveTime) {
  CloudBuilder b = xyzi();
  b.set(0, 0, 1.f);
  PointCloud2Msg cloud = b.build();
  cloud.header.stamp_ns = 0;
  EXPECT_EQ(convertPointCloud2(cloud, 42).scan.stamp_ns, 42);
}

// Found by fuzz_bag_messages: width 0 with a huge height once looped over every empty row.
TEST(PointCloud2, EmptyCloudsOfAnyHeightAreEmpty) {
  CloudBuilder b = xyzi();
  b.set(0, 0, 1.f);
  PointCloud2Msg cloud = b.build();
  cloud.width = 0;
  cloud.height = 0xFFFFFFFF;
  cloud.row_step = 0;
  EXPECT_EQ(convertPointCloud2(cloud, 0).scan.size(), 0u);
}

TEST(PointCloud2, UnreadableLayoutsThrow) {
  CloudBuilder no_z(16);
  no_z.field("x", 0, 7).field("y", 4, 7).set(0, 0, 1.f);
  EXPECT_THROW(convertPointCloud2(no_z.build(), 0), FormatError);

  CloudBuilder int_xyz(16);
  int_xyz.field("x", 0, 5).field("y", 4, 5).field("z", 8, 5).set(0, 0, 1);
  EXPECT_THROW(convertPointCloud2(int_xyz.build(), 0), FormatError);

  CloudBuilder past_step = xyzi();
  past_step.field("t", 14, 6).set(0, 0, 1.f);  // 14 + 4 > 16
  EXPECT_THROW(convertPointCloud2(past_step.build(), 0), FormatError);

  CloudBuilder bad_type = xyzi();
  bad_type.field("ring", 12, 9).set(0, 0, 1.f);
  EXPECT_THROW(convertPointCloud2(bad_type.build(), 0), FormatError);

  CloudBuilder short_data = xyzi();
  short_data.set(0, 0, 1.f);
  PointCloud2Msg cloud = short_data.build();
  cloud.width = 2;  // 32 bytes needed, 16 there
  EXPECT_THROW(convertPointCloud2(cloud, 0), FormatError);
  cloud.width = 1;
  cloud.height = 2;
  cloud.row_step = 8;  // < width * point_step
  EXPECT_THROW(convertPointCloud2(cloud, 0), FormatError);
}

}  // namespace
}  // namespace socc::sensors::bags
