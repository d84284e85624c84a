#include <gtest/gtest.h>
#include <sys/wait.h>

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

}  // namespace
}  // namespace socc::tools::test
