// ScanPreparer: the source's scans in order, each prepared (range filter) in a worker thread;
// an inconsistent scan is reported and the next ones follow; scans up to skip_until_seq pass
// unprepared; the source's errors surface where they happened.
#include <gtest/gtest.h>

#include <stdexcept>

#include "socc/odom/scan_preparer.hpp"

using namespace socc::odom;

namespace {

// Scans 0..count-1, each a point at 1 m (inside min_range) and one at 10 + seq m; scan `bad`
// has a label too many, scan `unreadable` throws (-1: none).
class NumberedScans : public ScanSource {
 public:
  NumberedScans(int count, int bad, int unreadable)
      : count_(count), bad_(bad), unreadable_(unreadable) {}
  std::optional<Scan> next() override {
    if (next_ == count_) return std::nullopt;
    if (next_ == unreadable_) throw std::runtime_error("unreadable scan");
    Scan scan;
    scan.seq = next_++;
    scan.name = "scan " + std::to_string(scan.seq);
    scan.cloud.points = {{1.f, 0.f, 0.f}, {10.f + static_cast<float>(scan.seq), 0.f, 0.f}};
    if (scan.seq == bad_) scan.cloud.labels = {0, 0, 0};
    return scan;
  }
  std::size_t remaining() const override { return static_cast<std::size_t>(count_ - next_); }

 private:
  int count_, bad_, unreadable_, next_ = 0;
};

}  // namespace

TEST(ScanPreparer, GivesEachScanPreparedInOrder) {
  NumberedScans source(4, -1, -1);
  ScanPreparer input(source, OdomConfig{}, -1);
  for (int k = 0; k < 4; ++k) {
    const std::optional<PreparedInput> next = input.next();
    ASSERT_TRUE(next && next->scan);
    EXPECT_EQ(next->seq, k);
    EXPECT_EQ(next->scan->seq, k);
    ASSERT_EQ(next->scan->cloud.size(), 1u);  // the point at 1 m is filtered out
    EXPECT_EQ(next->scan->cloud.points[0].x(), 10.f + static_cast<float>(k));
  }
  EXPECT_FALSE(input.next().has_value());
}

TEST(ScanPreparer, AnInconsistentScanIsReportedAndTheNextOnesFollow) {
  NumberedScans source(3, 1, -1);
  ScanPreparer input(source, OdomConfig{}, -1);
  EXPECT_TRUE(input.next()->scan.has_value());
  const std::optional<PreparedInput> bad = input.next();
  ASSERT_TRUE(bad.has_value());
  EXPECT_FALSE(bad->scan.has_value());
  EXPECT_FALSE(bad->skipped);
  EXPECT_EQ(bad->name, "scan 1");
  EXPECT_NE(bad->problem.find("bad scan"), std::string::npos) << bad->problem;
  EXPECT_EQ(input.next()->scan->seq, 2);
}

TEST(ScanPreparer, ScansIntegratedBeforeARestartPassUnprepared) {
  NumberedScans source(4, -1, -1);
  ScanPreparer input(source, OdomConfig{}, 1);
  for (int k = 0; k < 2; ++k) {
    const std::optional<PreparedInput> next = input.next();
    EXPECT_TRUE(next->skipped);
    EXPECT_FALSE(next->scan.has_value());
  }
  EXPECT_EQ(input.next()->scan->seq, 2);
}

TEST(ScanPreparer, AnUnreadableScanFailsWhereItIs) {
  NumberedScans source(5, -1, 2);
  ScanPreparer input(source, OdomConfig{}, -1);
  EXPECT_EQ(input.next()->seq, 0);
  EXPECT_EQ(input.next()->seq, 1);
  EXPECT_THROW(input.next(), std::runtime_error);
}
