#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include "scan_dir_fixture.hpp"
#include "socc/kitti_io.hpp"

namespace socc::tools::test {
namespace {
namespace fs = std::filesystem;

int run(const std::string& args) {
  const std::string cmd = std::string(SOCC_TO_LCMLOG_EXE) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class SoccToLcmlogCli : public TempDirTest {};

TEST_F(SoccToLcmlogCli, HelpAndExitCodes) {
  EXPECT_EQ(run("--help"), 0);
  EXPECT_NE(run(""), 0) << "input and output are required";

  fs::create_directories(dir_ / "seq" / "velodyne");
  Points p = {Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(4, 5, 6)};
  writeKittiBin(dir_ / "seq" / "velodyne" / "000000.bin", p);
  writeKittiBin(dir_ / "seq" / "velodyne" / "000001.bin", p);
  const fs::path log = dir_ / "out.lcmlog";
  ASSERT_EQ(run((dir_ / "seq").string() + " -o " + log.string() +
                " -q --robot-id cli_bot --rate 20 --start-utime 1000"),
            0);
  const std::vector<LoggedScan> events = readScanLog(log);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].channel, "SOCC/SCAN/cli_bot");
  EXPECT_EQ(events[1].scan.utime, 1000 + 50'000);

  EXPECT_EQ(run((dir_ / "seq").string() + " -o " + log.string() + " --robot-id 'bad/id'"), 2);
  std::ofstream(dir_ / "seq" / "velodyne" / "000001.bin") << "x";
  EXPECT_EQ(run((dir_ / "seq").string() + " -o " + log.string() + " -q"), 1);
  EXPECT_NE(run((dir_ / "seq").string() + " -o " + log.string() + " --rate -1"), 0);
}

// A recording (the real VLP-16 capture) through socc_sensors: one scan_t per complete sweep,
// stamped with the capture's clock, with intensities and the sensor's per-point times.
TEST_F(SoccToLcmlogCli, RecordingToLog) {
  const fs::path dir =
      fs::path(SOCC_SHARED_DATA_DIR) / "raw_sensors" / "01_velodyne_vlp16_veloview";
  if (!fs::exists(fs::path(SOCC_SHARED_DATA_DIR)))
    GTEST_SKIP() << SOCC_SHARED_DATA_DIR << " is absent";
  const fs::path log = dir_ / "vlp16.lcmlog";
  ASSERT_EQ(run((dir / "vlp-16-test-90deg-1-50-frames.pcap").string() + " -o " + log.string() +
                " -q --sensor vlp16 --calibration " + (dir / "VLP-16.xml").string()),
            0);
  const std::vector<LoggedScan> events = readScanLog(log);
  ASSERT_EQ(events.size(), 50u);
  for (std::size_t i = 0; i < events.size(); ++i) {
    const scan_t& s = events[i].scan;
    EXPECT_EQ(s.seq, static_cast<std::int64_t>(i));
    EXPECT_GT(s.num_points, 13000);
    EXPECT_EQ(s.num_times, s.num_points);
    EXPECT_EQ(s.num_intensities, s.num_points);
    EXPECT_EQ(s.num_labels, 0);
    EXPECT_NEAR(*std::max_element(s.time.begin(), s.time.end()), 0.05, 0.003);  // a 20 Hz turn
    EXPECT_GE(events[i].timestamp, s.utime);  // logged when the sweep ends
    if (i > 0) {
      EXPECT_NEAR(static_cast<double>(s.utime - events[i - 1].scan.utime), 50'000.0, 2'000.0);
    }
  }
  EXPECT_EQ(run((dir / "vlp-16-test-90deg-1-50-frames.pcap").string() + " -o " + log.string() +
                " -q --sensor hdl32e"),
            1)
      << "packets of another model: a clear error";
}

}  // namespace
}  // namespace socc::tools::test
