// The gravity reference from the input to the INTEGRATE request: a KITTI directory's
// gravity.txt indexes its frames (also in a frame range), bad files are errors, ScanPreparer
// passes it on unless use_gravity is off (--no-gravity), the odometry keeps it with its frame
// (also the held first one), and the request carries it (gravity_sigma 0 without); a
// recording's IMU attitude as each scan's reference (withImuAttitude).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "../temp_dir.hpp"
#include "socc/kitti_io.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/scan_preparer.hpp"
#include "socc/odom/scan_source.hpp"
#include "socc/rpc/map_client.hpp"

using namespace socc;
using namespace socc::odom;
using socc::sensors::StaticTransforms;
namespace fs = std::filesystem;

namespace {

// Four one-point scans; gravity.txt with the given lines (none: no file).
fs::path kittiDir(const std::string& name, const std::optional<std::string>& gravity) {
  const fs::path dir = socc::testing::processTempDir() / name;
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

// Scans at the given times [s], one point each.
class ListedScans final : public ScanSource {
 public:
  explicit ListedScans(std::vector<double> times, std::string frame = "lidar")
      : times_(std::move(times)), frame_(std::move(frame)) {}
  std::optional<Scan> next() override {
    if (next_ == times_.size()) return std::nullopt;
    Scan scan;
    scan.utime = static_cast<std::int64_t>(std::llround(times_[next_++] * 1e6));
    scan.cloud.points = {{10.f, 0.f, 0.f}};
    scan.frame_id = frame_;
    return scan;
  }
  std::size_t remaining() const override { return times_.size() - next_; }

 private:
  std::vector<double> times_;
  std::string frame_;
  std::size_t next_ = 0;
};

class ListedImu final : public sensors::ImuStream {
 public:
  explicit ListedImu(std::vector<sensors::ImuSample> samples) : samples_(std::move(samples)) {}
  std::optional<sensors::ImuSample> next() override {
    if (next_ == samples_.size()) return std::nullopt;
    return samples_[next_++];
  }

 private:
  std::vector<sensors::ImuSample> samples_;
  std::size_t next_ = 0;
};

// An IMU rolling about its x axis at 0.1 rad/s from t = 1 s, a sample every 20 ms over
// 1.00-1.20 s and 1.40-1.60 s (a 0.2 s gap between), the one at 1.10 s without an attitude.
std::unique_ptr<sensors::ImuStream> rollingImu(const Eigen::Matrix3d& covariance) {
  std::vector<sensors::ImuSample> samples;
  for (int k = 0; k <= 30; ++k) {
    if (k > 10 && k < 20) continue;
    sensors::ImuSample s;
    s.stamp_ns = 1'000'000'000 + k * 20'000'000LL;
    s.frame_id = "imu";
    if (k != 5)
      s.orientation =
          Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k * 0.02, Eigen::Vector3d::UnitX()));
    s.orientation_covariance = covariance;
    samples.push_back(s);
  }
  return std::make_unique<ListedImu>(std::move(samples));
}

std::vector<std::optional<GravityReference>> attitudes(ImuAttitude imu,
                                                       const std::vector<double>& times,
                                                       const std::string& frame = "lidar") {
  auto source = withImuAttitude(std::make_unique<ListedScans>(times, frame), std::move(imu));
  std::vector<std::optional<GravityReference>> out;
  while (std::optional<Scan> scan = source->next()) out.push_back(scan->gravity);
  return out;
}

}  // namespace

// The attitude between the samples on either side of a scan's time, turned into the sensor
// frame by the mounting; none before the IMU's first sample, across a gap of more than 0.1 s,
// after its last; sigma as configured, else the samples' covariance, else 0.5 deg.
TEST(GravitySource, AnImuAttitudeIsInterpolatedAtEachScansTime) {
  ImuAttitude imu;
  imu.stream = rollingImu(Eigen::Vector3d(1e-4, 4e-4, 1.0).asDiagonal());
  imu.sensor_R_imu = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<std::optional<GravityReference>> g =
      attitudes(std::move(imu), {0.9, 1.05, 1.1, 1.3, 1.5, 1.7});
  ASSERT_EQ(g.size(), 6u);
  EXPECT_FALSE(g[0]);  // before the IMU
  EXPECT_FALSE(g[3]);  // in the gap
  EXPECT_FALSE(g[5]);  // after it
  // Rolled by angle about the IMU's x: up (0, sin, cos) in the IMU frame, (-sin, 0, cos) in the
  // sensor frame whose x is the IMU's y.
  for (const auto& [i, angle] : {std::pair{1, 0.005}, {2, 0.01}, {4, 0.05}}) {
    ASSERT_TRUE(g[static_cast<std::size_t>(i)]) << i;
    const GravityReference& r = *g[static_cast<std::size_t>(i)];
    EXPECT_LT((r.up - Eigen::Vector3d(-std::sin(angle), 0.0, std::cos(angle))).norm(), 1e-9) << i;
    EXPECT_DOUBLE_EQ(r.sigma, 0.02) << i;  // sqrt of the larger of roll's and pitch's variance
  }
  ImuAttitude stated;
  stated.stream = rollingImu(Eigen::Vector3d(1e-4, 4e-4, 1.0).asDiagonal());
  stated.sensor_R_imu = Eigen::Matrix3d::Identity();
  stated.sigma = 0.003;
  EXPECT_DOUBLE_EQ(attitudes(std::move(stated), {1.05})[0]->sigma, 0.003);
  ImuAttitude unknown;
  unknown.stream = rollingImu(Eigen::Matrix3d::Zero());
  unknown.sensor_R_imu = Eigen::Matrix3d::Identity();
  EXPECT_DOUBLE_EQ(attitudes(std::move(unknown), {1.05})[0]->sigma, 0.5 * M_PI / 180.0);
}

// Without a stated mounting, the recording's static transforms give it by the scans' and the
// IMU's frame names; without a chain between them the first scan is an error that says what
// to state, never a guessed mounting.
std::string mountingError(StaticTransforms mounts, const std::string& frame) {
  ImuAttitude imu;
  imu.stream = rollingImu(Eigen::Matrix3d::Zero());
  imu.mounts = std::move(mounts);
  try {
    attitudes(std::move(imu), {1.05}, frame);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(GravitySource, AnImusMountingComesFromTheRecordingsStaticTransforms) {
  ImuAttitude imu;
  imu.stream = rollingImu(Eigen::Matrix3d::Zero());
  Eigen::Isometry3d base_T_imu = Eigen::Isometry3d::Identity();
  base_T_imu.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  base_T_imu.translation() = Eigen::Vector3d(0.5, 0.0, 0.2);
  imu.mounts.add("base_link", "lidar", Eigen::Isometry3d::Identity());
  imu.mounts.add("base_link", "imu", base_T_imu);
  const std::optional<GravityReference> g = attitudes(std::move(imu), {1.05})[0];
  ASSERT_TRUE(g);
  EXPECT_LT((g->up - Eigen::Vector3d(-std::sin(0.005), 0.0, std::cos(0.005))).norm(), 1e-9);

  const std::string none = mountingError({}, "lidar");
  EXPECT_NE(none.find("imu_roll_deg, imu_pitch_deg and imu_yaw_deg"), std::string::npos) << none;
  EXPECT_NE(none.find("(lidar) to the IMU's (imu)"), std::string::npos) << none;
  EXPECT_NE(none.find("(none)"), std::string::npos) << none;
  StaticTransforms other;
  other.add("base_link", "camera", Eigen::Isometry3d::Identity());
  // An IMU without any attitude needs no mounting: its scans just get no reference.
  ImuAttitude rates_only;
  rates_only.stream = std::make_unique<ListedImu>(std::vector<sensors::ImuSample>(3));
  EXPECT_FALSE(attitudes(std::move(rates_only), {0.0})[0]);
  const std::string unjoined = mountingError(other, "");
  EXPECT_NE(unjoined.find("they name none"), std::string::npos) << unjoined;
  EXPECT_NE(unjoined.find("base_link -> camera"), std::string::npos) << unjoined;
}

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
