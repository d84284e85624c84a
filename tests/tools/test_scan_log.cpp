#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "scan_dir_fixture.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"
#include "socc/tools/scan_directory.hpp"
#include "socc/tools/scan_log_writer.hpp"

namespace socc::tools::test {
namespace {
namespace fs = std::filesystem;

constexpr std::int64_t kStart = 1'600'000'000'000'000;

ScanLogOptions quietOptions(const std::string& robot) {
  ScanLogOptions o;
  o.robot_id = robot;
  o.start_utime = kStart;
  o.progress = false;
  return o;
}

Points somePoints(std::size_t n, float offset) {
  Points p;
  for (std::size_t i = 0; i < n; ++i) p.emplace_back(offset + static_cast<float>(i), 1.f, -1.f);
  return p;
}

// A tiny KITTI directory: scans 000005..000007 with labels, point times and times.txt.
void writeTinyKitti(const fs::path& root, bool with_times) {
  fs::create_directories(root / "velodyne");
  fs::create_directories(root / "labels");
  fs::create_directories(root / "point_times");
  for (int f = 5; f <= 7; ++f) {
    const std::string stem = "00000" + std::to_string(f);
    const std::size_t n = static_cast<std::size_t>(f);
    const std::vector<float> refl(n, 0.25f);
    writeKittiBin(root / "velodyne" / (stem + ".bin"), somePoints(n, static_cast<float>(f)), &refl);
    // raw 10 = car, 40 = road; upper 16 bits are the instance id and must be ignored.
    std::vector<std::uint32_t> raw(n, 40);
    raw[0] = (7u << 16) | 10u;
    writeSemanticKittiLabels(root / "labels" / (stem + ".label"), raw);
    const std::vector<float> t(n, 0.05f);
    std::ofstream(root / "point_times" / (stem + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(t.data()), static_cast<std::streamsize>(n * 4));
  }
  if (with_times) std::ofstream(root / "times.txt") << "0\n0.1\n0.2\n0.3\n0.4\n1.0\n1.1\n1.25\n";
}

TEST(ScanLog, KittiFirst16) {
  const fs::path data = fs::path(SOCC_SHARED_DATA_DIR) / "kitti_00_first16";
  if (!fs::is_directory(data)) GTEST_SKIP() << "shared data not found: " << data;
  const fs::path log =
      fs::temp_directory_path() / ("socc_test_kitti16_" + std::to_string(::getpid()) + ".lcmlog");

  const ScanDirectory dir = openScanDirectory(data);
  ASSERT_EQ(dir.scans.size(), 16u);
  const ScanLogSummary summary = writeScanLog(dir, log, quietOptions("robot7"));
  EXPECT_EQ(summary.scans, 16u);

  const std::vector<LoggedScan> events = readScanLog(log);
  fs::remove(log);
  ASSERT_EQ(events.size(), 16u);
  for (std::size_t i = 0; i < events.size(); ++i) {
    const LoggedScan& e = events[i];
    EXPECT_EQ(e.channel, "SOCC/SCAN/robot7");
    EXPECT_EQ(e.scan.robot_id, "robot7");
    EXPECT_EQ(e.scan.seq, static_cast<std::int64_t>(i));
    const Points points = readKittiBin(dir.scans[i]);
    EXPECT_EQ(e.scan.num_points, static_cast<std::int32_t>(points.size()));
    EXPECT_EQ(e.scan.num_intensities, e.scan.num_points);
    EXPECT_EQ(e.scan.num_labels, i == 0 ? e.scan.num_points : 0) << "only frame 0 has labels";
    EXPECT_EQ(e.scan.utime, kStart + static_cast<std::int64_t>(i) * 100'000) << "10 Hz default";
    EXPECT_EQ(e.timestamp, e.scan.utime);
    if (i > 0) {
      EXPECT_EQ(e.timestamp - events[i - 1].timestamp, 100'000);
    }
  }
  ASSERT_GT(events[0].scan.num_points, 0);
  const Points first = readKittiBin(dir.scans[0]);
  EXPECT_FLOAT_EQ(events[0].scan.xyz[0][0], first[0].x());
  EXPECT_FLOAT_EQ(events[0].scan.xyz[2].back(), first.back().z());
  for (const std::uint8_t c : events[0].scan.label) EXPECT_LT(c, kNumClasses);
}

class TinyScanLog : public TempDirTest {};

TEST_F(TinyScanLog, LabelsPointTimesAndTimesTxt) {
  writeTinyKitti(dir_ / "seq", true);
  const ScanDirectory dir = openScanDirectory(dir_ / "seq");
  EXPECT_EQ(dir.format, ScanFormat::kKitti);
  writeScanLog(dir, dir_ / "out.lcmlog", quietOptions("r1"));
  const std::vector<LoggedScan> events = readScanLog(dir_ / "out.lcmlog");
  ASSERT_EQ(events.size(), 3u);
  // Frames 5..7 take lines 5..7 of times.txt (1.0, 1.1, 1.25 s): real gaps, not the rate.
  EXPECT_EQ(events[0].scan.utime, kStart);
  EXPECT_EQ(events[1].scan.utime, kStart + 100'000);
  EXPECT_EQ(events[2].scan.utime, kStart + 250'000);
  for (std::size_t i = 0; i < 3; ++i) {
    const scan_t& s = events[i].scan;
    EXPECT_EQ(s.num_points, static_cast<std::int32_t>(5 + i));
    ASSERT_EQ(s.num_labels, s.num_points);
    EXPECT_EQ(s.label[0], kCar);
    EXPECT_EQ(s.label[1], kRoad);
    ASSERT_EQ(s.num_times, s.num_points);
    EXPECT_FLOAT_EQ(s.time[0], 0.05f);
    EXPECT_FLOAT_EQ(s.intensity[0], 0.25f);
    EXPECT_FLOAT_EQ(s.xyz[0][1], static_cast<float>(5 + i) + 1.f);  // x of point 1
  }
}

TEST_F(TinyScanLog, RateWithoutTimesTxt) {
  writeTinyKitti(dir_ / "seq", false);
  ScanLogOptions o = quietOptions("r1");
  o.rate_hz = 4.0;
  const std::vector<std::int64_t> t = scanTimestamps(openScanDirectory(dir_ / "seq"), o);
  EXPECT_EQ(t, (std::vector<std::int64_t>{kStart, kStart + 250'000, kStart + 500'000}));
  o.rate_hz = 0.0;
  EXPECT_THROW(scanTimestamps(openScanDirectory(dir_ / "seq"), o), std::invalid_argument);
}

TEST_F(TinyScanLog, PcdDirectory) {
  std::ofstream(dir_ / "a.pcd") << "VERSION .7\nFIELDS x y z intensity label\nSIZE 4 4 4 4 4\n"
                                   "TYPE F F F F U\nCOUNT 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                                   "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
                                   "1 2 3 0.5 10\nnan nan nan 0 0\n4 5 6 0.75 50\n";
  std::ofstream(dir_ / "b.pcd") << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                                   "COUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
                                   "POINTS 1\nDATA ascii\n7 8 9\n";
  const ScanDirectory dir = openScanDirectory(dir_);
  ASSERT_EQ(dir.format, ScanFormat::kPcd);
  writeScanLog(dir, dir_ / "pcd.lcmlog", quietOptions("r2"));
  const std::vector<LoggedScan> events = readScanLog(dir_ / "pcd.lcmlog");
  ASSERT_EQ(events.size(), 2u);
  const scan_t& a = events[0].scan;
  ASSERT_EQ(a.num_points, 2) << "the NaN point is dropped";
  EXPECT_FLOAT_EQ(a.xyz[2][1], 6.f);  // z of point 1
  ASSERT_EQ(a.num_intensities, 2);
  EXPECT_FLOAT_EQ(a.intensity[1], 0.75f);
  ASSERT_EQ(a.num_labels, 2);
  EXPECT_EQ(a.label[0], kCar);
  EXPECT_EQ(a.label[1], kBuilding);
  EXPECT_EQ(events[1].scan.num_points, 1);
  EXPECT_EQ(events[1].scan.num_labels, 0);
  EXPECT_EQ(events[1].channel, "SOCC/SCAN/r2");
}

TEST_F(TinyScanLog, BadInputIsAClearErrorAndLeavesNoLog) {
  EXPECT_THROW(openScanDirectory(dir_), std::runtime_error) << "empty directory";
  EXPECT_THROW(openScanDirectory(dir_ / "missing"), std::runtime_error);

  writeTinyKitti(dir_ / "seq", false);
  std::ofstream(dir_ / "seq" / "times.txt") << "0\n0.1\n";  // no line for frames 5..7
  try {
    openScanDirectory(dir_ / "seq");
    ADD_FAILURE() << "short times.txt accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("none for scan 000005.bin"), std::string::npos)
        << e.what();
  }
  std::ofstream(dir_ / "seq" / "times.txt") << "0\n0\n0\n0\n0\n2\n1\n3\n";
  EXPECT_THROW(scanTimestamps(openScanDirectory(dir_ / "seq"), quietOptions("r")),
               std::invalid_argument);

  fs::remove(dir_ / "seq" / "times.txt");
  writeSemanticKittiLabels(dir_ / "seq" / "labels" / "000006.label", {1, 2});  // 2 for 6 points
  const fs::path log = dir_ / "bad.lcmlog";
  EXPECT_THROW(writeScanLog(openScanDirectory(dir_ / "seq"), log, quietOptions("r")),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(log));

  std::ofstream(dir_ / "seq" / "velodyne" / "000006.bin") << "garbage";  // not 16-byte records
  EXPECT_THROW(loadScan(openScanDirectory(dir_ / "seq"), 1), std::runtime_error);
}

TEST_F(TinyScanLog, MalformedPcdIsAnErrorNotACrash) {
  const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  const std::vector<std::string> bad = {
      "not a pcd",
      "",
      "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",  // no FIELDS
      "FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
      fields + "WIDTH 2\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n",  // 2 * 1 != 1
      fields + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA zip\n",
      fields + "WIDTH 1000\nHEIGHT 1\nPOINTS 1000\nDATA binary\nshort",  // truncated body
      "FIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
      // PCL reads on past DATA while lines look like header lines: bodies that start so.
      fields + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\nCOLUMNS" + std::string(5, '\0'),
      fields + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n\n# c\n  SIZE\n" + std::string(12, '\1'),
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    const fs::path f = dir_ / ("bad" + std::to_string(i) + ".pcd");
    std::ofstream(f, std::ios::binary) << bad[i];
    EXPECT_THROW(readPcdScan(f), std::runtime_error) << "case " << i;
  }
}

}  // namespace
}  // namespace socc::tools::test
