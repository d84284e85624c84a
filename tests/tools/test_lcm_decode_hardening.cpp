// The generated decoders are patched (cmake/PatchLcmDecode.cmake) so that lengths read from a
// message are checked against the bytes left before anything is allocated.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "socc/request_header_t.hpp"
#include "socc/scan_t.hpp"

namespace {

std::vector<std::uint8_t> encodedScan() {
  socc::scan_t s{};
  s.robot_id = "r1";
  s.num_points = 2;
  s.xyz = {{1.f, 2.f, 3.f}, {4.f, 5.f, 6.f}};
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

}  // namespace
