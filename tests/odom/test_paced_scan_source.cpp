// atRecordedPace: the wrapped source's scans, unchanged and in order, each no earlier than its
// time stamp says (scaled by the rate) after the first; a scan asked for late comes at once.
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "socc/odom/scan_source.hpp"

using namespace socc::odom;
using Clock = std::chrono::steady_clock;

namespace {

// count scans, period_us apart, then the end.
class StampedSource : public ScanSource {
 public:
  StampedSource(int count, std::int64_t period_us) : count_(count), period_us_(period_us) {}
  std::optional<Scan> next() override {
    if (next_ == count_) return std::nullopt;
    Scan scan;
    scan.seq = next_;
    scan.utime = 1'000'000'000 + period_us_ * next_++;
    return scan;
  }
  std::size_t remaining() const override { return static_cast<std::size_t>(count_ - next_); }

 private:
  int count_, next_ = 0;
  std::int64_t period_us_;
};

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

TEST(PacedScanSource, HandsOutEachScanNoEarlierThanItsTimeAtTheRate) {
  // 5 scans 0.1 s apart at twice the recorded pace: the last one 0.2 s after the first.
  const auto source = atRecordedPace(std::make_unique<StampedSource>(5, 100'000), 2.0);
  EXPECT_TRUE(source->live());
  EXPECT_EQ(source->remaining(), 5u);
  const Clock::time_point start = Clock::now();
  for (int k = 0; k < 5; ++k) {
    const std::optional<Scan> scan = source->next();
    ASSERT_TRUE(scan.has_value());
    EXPECT_EQ(scan->seq, k);
    EXPECT_GE(secondsSince(start), 0.05 * k);
  }
  EXPECT_FALSE(source->next().has_value());
}

TEST(PacedScanSource, AScanAskedForLateIsNotDropped) {
  const auto source = atRecordedPace(std::make_unique<StampedSource>(3, 10'000), 1.0);
  EXPECT_EQ(source->next()->seq, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the loop falls behind
  EXPECT_EQ(source->next()->seq, 1);
  EXPECT_EQ(source->next()->seq, 2);
  EXPECT_FALSE(source->next().has_value());
}

TEST(PacedScanSource, RefusesARateThatIsNotPositive) {
  EXPECT_THROW(atRecordedPace(std::make_unique<StampedSource>(1, 1), 0.0), std::invalid_argument);
  EXPECT_THROW(atRecordedPace(std::make_unique<StampedSource>(1, 1), -1.0), std::invalid_argument);
}
