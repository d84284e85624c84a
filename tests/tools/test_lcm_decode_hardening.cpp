// The generated decoders are patched (cmake/PatchLcmDecode.cmake) so that lengths read from a
// message are checked against the bytes left before anything is allocated; and the
// structure-of-arrays layout of the 2-D fields (socc/wire_arrays.hpp, docs/lcm.md).
#include <gtest/gtest.h>

#include <cstring>

// Inlined into a test body, the generated decode's hash read (through __int64_t_decode_array)
// is reported as maybe-uninitialized: GCC 12 loses track of the pointer it is written through.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/request_header_t.hpp"
#include "socc/scan_t.hpp"
#include "socc/wire_arrays.hpp"

namespace {

std::vector<std::uint8_t> encodedScan() {
  socc::scan_t s{};
  s.robot_id = "r1";
  s.num_points = 2;
  s.xyz = {{1.f, 4.f}, {2.f, 5.f}, {3.f, 6.f}};  // points (1, 2, 3) and (4, 5, 6) by axis
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(s.getEncodedSize()));
  s.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

void putBigEndian(std::vector<std::uint8_t>& buf, std::size_t at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) buf[at + i] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
}

// Layout of scan_t: hash(8) utime(8) robot_id(len 4 + "r1\0") seq(8) num_points(4) ...
constexpr std::size_t kRobotIdLen = 16;
constexpr std::size_t kNumPoints = kRobotIdLen + 4 + 3 + 8;

int decode(const std::vector<std::uint8_t>& buf) {
  socc::scan_t s;
  return s.decode(buf.data(), 0, static_cast<int>(buf.size()));
}

TEST(LcmDecodeHardening, ValidScanDecodes) {
  const auto buf = encodedScan();
  EXPECT_EQ(decode(buf), static_cast<int>(buf.size()));
}

TEST(LcmDecodeHardening, ImpossibleArrayLengthsAreRejectedBeforeAllocating) {
  for (const std::int32_t n : {0x7fffffff, -1, -2147483647 - 1, 1000}) {
    auto buf = encodedScan();
    putBigEndian(buf, kNumPoints, n);
    EXPECT_LT(decode(buf), 0) << "num_points " << n;  // no exception, no huge allocation
  }
}

TEST(LcmDecodeHardening, BadStringLengthsAreRejected) {
  for (const std::int32_t n : {0, -1, -100, 0x7fffffff}) {
    auto buf = encodedScan();
    putBigEndian(buf, kRobotIdLen, n);
    EXPECT_LT(decode(buf), 0) << "string length " << n;
  }
}

TEST(LcmDecodeHardening, RowCountsAndRowLengthsAreChecked) {
  // chunk_reply_t.class_prob[num_classes][n_stats]: both the row count and the row length come
  // from the wire.
  socc::chunk_reply_t r{};
  r.n_stats = 1;
  r.num_classes = 2;
  r.mean = {{1.f}, {2.f}, {3.f}};
  r.covariance.assign(6, {0.f});
  r.count = {1};
  r.log_odds = {0.f};
  r.class_prob = {{0.25f}, {0.75f}};
  ASSERT_EQ(socc::wire::checkArrays(r), "");
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(r.getEncodedSize()));
  ASSERT_EQ(r.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  socc::chunk_reply_t back;
  ASSERT_EQ(back.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  EXPECT_EQ(back.class_prob, r.class_prob);
  // num_classes is the int32 before mean (3 x 4 bytes), covariance (6 x 4), count, log_odds
  // (4 each), class_prob (2 x 4), n_free (4): 56 bytes from the end.
  const std::size_t num_classes = buf.size() - 56 - 4;
  const std::size_t n_stats = num_classes - 4;
  for (const std::int32_t n : {0x7fffffff, -1, 1000}) {
    auto bad = buf;
    putBigEndian(bad, num_classes, n);
    EXPECT_LT(back.decode(bad.data(), 0, static_cast<int>(bad.size())), 0) << "num_classes " << n;
    bad = buf;
    putBigEndian(bad, n_stats, n);
    EXPECT_LT(back.decode(bad.data(), 0, static_cast<int>(bad.size())), 0) << "n_stats " << n;
  }
}

TEST(WireLayout, PointsAreEncodedAxisByAxis) {
  // After scan_t's num_points: all x, then all y, then all z (big-endian floats).
  const auto buf = encodedScan();
  std::vector<float> values;
  for (std::size_t at = kNumPoints + 4; at < kNumPoints + 4 + 6 * 4; at += 4) {
    std::uint32_t u = 0;
    for (int i = 0; i < 4; ++i) u = (u << 8) | buf[at + i];
    float f;
    std::memcpy(&f, &u, sizeof f);
    values.push_back(f);
  }
  EXPECT_EQ(values, (std::vector<float>{1.f, 4.f, 2.f, 5.f, 3.f, 6.f}));
}

TEST(WireLayout, PointRowsRoundTrip) {
  const socc::Points points = {{1.f, 2.f, 3.f}, {4.f, 5.f, 6.f}, {-7.f, 8.5f, 0.f}};
  socc::wire::Rows<float> xyz;
  socc::wire::pointsToRows(points, xyz);
  ASSERT_EQ(xyz.size(), 3u);
  EXPECT_EQ(xyz[1], (std::vector<float>{2.f, 5.f, 8.5f}));
  EXPECT_EQ(socc::wire::column(xyz, 2), (std::vector<float>{-7.f, 8.5f, 0.f}));
  EXPECT_EQ(socc::wire::pointsFromRows(xyz), points);
  EXPECT_TRUE(socc::wire::pointsFromRows({}).empty());
  xyz[2].pop_back();
  EXPECT_THROW(socc::wire::pointsFromRows(xyz), std::invalid_argument);
}

TEST(WireLayout, CheckArraysCatchesRowsThatEncodeWouldOverrun) {
  socc::scan_t s{};
  s.num_points = 2;
  s.xyz = {{1.f, 4.f}, {2.f, 5.f}, {3.f, 6.f}};
  EXPECT_EQ(socc::wire::checkArrays(s), "");
  socc::scan_t bad = s;
  bad.xyz[2].pop_back();  // encode() would read one float past the row
  EXPECT_NE(socc::wire::checkArrays(bad), "");
  bad = s;
  bad.xyz.pop_back();  // a missing row
  EXPECT_NE(socc::wire::checkArrays(bad), "");
  bad = s;
  bad.xyz = {{1.f, 2.f, 3.f}, {4.f, 5.f, 6.f}};  // the old point-major layout
  EXPECT_NE(socc::wire::checkArrays(bad), "");
  bad = s;
  bad.num_intensities = 1;
  EXPECT_NE(socc::wire::checkArrays(bad), "");
  EXPECT_EQ(socc::wire::checkArrays(socc::scan_t{}), "") << "empty vectors are fine for count 0";

  // A decoded message always passes, including the rows of empty arrays.
  const auto buf = encodedScan();
  socc::scan_t decoded;
  ASSERT_GT(decoded.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
  EXPECT_EQ(socc::wire::checkArrays(decoded), "");
  socc::chunk_reply_t empty_reply{};
  std::vector<std::uint8_t> reply_buf(static_cast<std::size_t>(empty_reply.getEncodedSize()));
  empty_reply.encode(reply_buf.data(), 0, static_cast<int>(reply_buf.size()));
  ASSERT_GT(empty_reply.decode(reply_buf.data(), 0, static_cast<int>(reply_buf.size())), 0);
  EXPECT_EQ(empty_reply.index.size(), 3u) << "decode() yields the rows, empty";
  EXPECT_EQ(socc::wire::checkArrays(empty_reply), "");
}

}  // namespace

TEST(PointQuantization, RoundTripWithinHalfTheResolution) {
  const socc::Points points = {{99.9f, -0.0004f, 3.3f}, {-100.f, 12.345f, -1.7f}, {0.f, 0.f, 0.f}};
  socc::wire::Rows<std::int16_t> rows;
  const float resolution = socc::wire::quantizePoints(points, rows);
  EXPECT_NEAR(resolution, 100.f / 32766.f, 1e-9f);  // ~3 mm for a scan reaching 100 m
  const socc::Points back = socc::wire::pointsFromQuantized(rows, resolution);
  ASSERT_EQ(back.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_LE((back[i] - points[i]).cwiseAbs().maxCoeff(), 0.5f * resolution * 1.001f) << i;
  EXPECT_THROW(socc::wire::quantizePoints({{std::nanf(""), 0.f, 0.f}}, rows),
               std::invalid_argument);
  EXPECT_THROW(socc::wire::pointsFromQuantized(rows, 0.f), std::invalid_argument);
  EXPECT_THROW(socc::wire::pointsFromQuantized(rows, std::nanf("")), std::invalid_argument);
  // No point (3 empty rows): nothing to scale, whatever the resolution (the fuzzer's case).
  EXPECT_TRUE(socc::wire::pointsFromQuantized({{}, {}, {}}, 0.f).empty());
}
