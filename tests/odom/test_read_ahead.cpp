// readAhead: the scans of the wrapped source in order, its count, and its errors where they
// happened (the scan after the last good one), read one scan ahead in a worker thread.
#include <gtest/gtest.h>

#include <stdexcept>

#include "socc/odom/scan_source.hpp"

using namespace socc::odom;

namespace {

// Scans 0..count-1, then the end; throws instead of scan `bad` (-1: never).
class CountingSource : public ScanSource {
 public:
  CountingSource(int count, int bad) : count_(count), bad_(bad) {}
  std::optional<Scan> next() override {
    if (next_ == count_) return std::nullopt;
    if (next_ == bad_) throw std::runtime_error("unreadable scan " + std::to_string(next_));
    Scan scan;
    scan.seq = next_++;
    scan.cloud.points.emplace_back(static_cast<float>(scan.seq), 0.f, 0.f);
    return scan;
  }
  std::size_t remaining() const override { return static_cast<std::size_t>(count_ - next_); }

 private:
  int count_, bad_, next_ = 0;
};

}  // namespace

TEST(ReadAhead, GivesTheScansInOrderAndTheirCount) {
  const auto source = readAhead(std::make_unique<CountingSource>(5, -1));
  EXPECT_EQ(source->remaining(), 5u);
  for (int k = 0; k < 5; ++k) {
    const std::optional<Scan> scan = source->next();
    ASSERT_TRUE(scan.has_value());
    EXPECT_EQ(scan->seq, k);
    EXPECT_EQ(scan->cloud.points[0].x(), static_cast<float>(k));
    EXPECT_EQ(source->remaining(), static_cast<std::size_t>(4 - k));
  }
  EXPECT_FALSE(source->next().has_value());
}

TEST(ReadAhead, AnUnreadableScanFailsWhereItIs) {
  const auto source = readAhead(std::make_unique<CountingSource>(5, 2));
  EXPECT_EQ(source->next()->seq, 0);
  EXPECT_EQ(source->next()->seq, 1);
  EXPECT_THROW(source->next(), std::runtime_error);
}

TEST(ReadAhead, StopsEarlyWithoutWaitingForTheRest) {
  const auto source = readAhead(std::make_unique<CountingSource>(1000, -1));
  EXPECT_EQ(source->next()->seq, 0);  // destroyed with a scan read ahead
}
