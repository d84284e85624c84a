// The gravity reference from the input to the INTEGRATE request: a KITTI directory's
// gravity.txt indexes its frames (also in a frame range), bad files are errors, ScanPreparer
// passes it on unless use_gravity is off (--no-gravity), the odometry keeps it with its frame
// (also the held first one), and the request carries it (gravity_sigma 0 without).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "socc/kitti_io.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/scan_preparer.hpp"
#include "socc/odom/scan_source.hpp"
#include "socc/rpc/map_client.hpp"

using namespace socc;
using namespace socc::odom;
namespace fs = std::filesystem;

namespace {

// Four one-point scans; gravity.txt with the given lines (none: no file).
fs::path kittiDir(const std::string& name, const std::optional<std::string>& gravity) {
  const fs::path dir =
      fs::temp_directory_path() / ("socc_gravity_src_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "velodyne");
  for (int k = 0; k < 4; ++k) {
    const Points points = {{10.f + static_cast<float>(k), 0.f, 0.f}};
    writeKittiBin(dir / "velodyne" / ("00000" + std::to_string(k) + ".bin"), points);
  }
  if (gravity) std::ofstream(dir / "gravity.txt") << *gravity;
  return dir;
}

const char* kFourLines =
    "0 0 1 0.001\n"
    "0 0 1 0\n"
    "0 1 0 0.002\n"
    "1 0 0 0.003\n";

std::string openError(const fs::path& dir) {
  try {
    openKittiDirectory(dir, {});
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(GravitySource, KittiDirectoryGivesEachFrameItsLine) {
  auto source = openKittiDirectory(kittiDir("good", kFourLines), {});
  std::vector<std::optional<Scan>> scans;
  while (auto scan = source->next()) scans.push_back(std::move(scan));
  ASSERT_EQ(scans.size(), 4u);
  ASSERT_TRUE(scans[0]->gravity);
  EXPECT_DOUBLE_EQ(scans[0]->gravity->sigma, 0.001);
  EXPECT_FALSE(scans[1]->gravity);  // sigma 0: none for that frame
  EXPECT_EQ(scans[3]->gravity->up, Eigen::Vector3d::UnitX());
}

TEST(GravitySource, AFrameRangeReadsTheFramesLines) {
  auto source = openKittiDirectory(kittiDir("range", kFourLines), {2, 3});
  const std::optional<Scan> first = source->next();
  ASSERT_TRUE(first && first->gravity);
  EXPECT_EQ(first->seq, 2);
  EXPECT_EQ(first->gravity->up, Eigen::Vector3d::UnitY());
  EXPECT_DOUBLE_EQ(source->next()->gravity->sigma, 0.003);
  EXPECT_FALSE(source->next());
}

TEST(GravitySource, NoFileNoGravity) {
  auto source = openKittiDirectory(kittiDir("none", std::nullopt), {});
  EXPECT_FALSE(source->next()->gravity);
}

TEST(GravitySource, BadFilesAreClearErrors) {
  const std::string short_file = openError(kittiDir("short", "0 0 1 0.001\n0 0 1 0.001\n"));
  EXPECT_NE(short_file.find("gravity.txt: 2 lines for 4 scans"), std::string::npos) << short_file;
  const std::string bad_line =
      openError(kittiDir("bad", "0 0 1 0.001\n0 0 1 0.001\n0 0 2 0.001\n0 0 1 0.001\n"));
  EXPECT_NE(bad_line.find("gravity.txt:3: up vector of length"), std::string::npos) << bad_line;
  const std::string negative = openError(kittiDir("negative", "0 0 1 -1\n"));
  EXPECT_NE(negative.find("gravity.txt:1: negative sigma"), std::string::npos) << negative;
}

TEST(GravitySource, PreparerPassesItOnUnlessSwitchedOff) {
  for (const bool use : {true, false}) {
    SCOPED_TRACE(use);
    auto source = openKittiDirectory(kittiDir("prep", kFourLines), {});
    OdomConfig config;
    config.use_gravity = use;
    ScanPreparer input(*source, config, -1);
    const std::optional<PreparedInput> next = input.next();
    ASSERT_TRUE(next && next->scan);
    EXPECT_EQ(next->scan->gravity.has_value(), use);
  }
}

TEST(GravitySource, OdometryKeepsItWithTheFrame) {
  OdomConfig config;
  Odometry odometry(config, Eigen::Isometry3d::Identity());
  LabeledCloud cloud;
  for (int i = 0; i < 50; ++i) cloud.points.push_back({10.f, 0.1f * i, 0.f});
  cloud.times.assign(cloud.points.size(), 0.f);  // with times the first scan is held
  PreparedScan scan = odometry.prepare(cloud, 0, 0);
  scan.gravity = GravityReference{Eigen::Vector3d::UnitZ(), 0.004};
  const FrameEstimate held = odometry.registerFrame(scan, LocalMap{});
  EXPECT_TRUE(held.held);
  EXPECT_DOUBLE_EQ(held.gravity->sigma, 0.004);
  PreparedScan second = odometry.prepare(cloud, 1, 100000);  // no reference for this one
  const FrameEstimate estimate = odometry.registerFrame(second, LocalMap{});
  EXPECT_FALSE(estimate.gravity);
  const std::optional<FrameEstimate> first = odometry.takeReleasedFrame();
  ASSERT_TRUE(first);
  ASSERT_TRUE(first->gravity);
  EXPECT_DOUBLE_EQ(first->gravity->sigma, 0.004);
}

TEST(GravitySource, TheRequestCarriesIt) {
  LabeledCloud cloud;
  cloud.points = {{1.f, 2.f, 3.f}};
  const Eigen::Vector3d up = Eigen::Vector3d(0.01, 0.02, 1.0).normalized();
  const integrate_request_t with = rpc::makeIntegrateRequest(
      1, 100000, Eigen::Isometry3d::Identity(), cloud, GravityReference{up, 5e-4});
  EXPECT_FLOAT_EQ(with.gravity_sigma, 5e-4f);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(with.gravity_up[i], static_cast<float>(up[i]));
  const integrate_request_t without =
      rpc::makeIntegrateRequest(1, 100000, Eigen::Isometry3d::Identity(), cloud);
  EXPECT_EQ(without.gravity_sigma, 0.f);
}
