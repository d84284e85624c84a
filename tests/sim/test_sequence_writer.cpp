// The written KITTI layout: readable with the shared readers, deterministic per seed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "socc/gravity_file.hpp"
#include "socc/kitti_io.hpp"
#include "socc/sim/beam_calibration.hpp"
#include "socc/sim/realism.hpp"
#include "socc/sim/sequence_writer.hpp"

namespace socc::sim {
namespace {

namespace fs = std::filesystem;

fs::path tempRoot() {
  return fs::temp_directory_path() / ("socc_sim_" + std::to_string(::getpid()));
}

fs::path tempDir(const std::string& name) {
  const fs::path d = tempRoot() / name;
  fs::remove_all(d);
  return d;
}

class SequenceWriter : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(tempRoot()); }
};

fs::path generate(const std::string& name, std::uint64_t seed, std::size_t frames = 3,
                  const ImuErrors& imu = {}, std::size_t every = 1) {
  SequenceOptions options;
  options.frames = frames;
  options.every = every;
  SceneOptions scene_options;
  scene_options.frames = sweepsSpanned(options);
  scene_options.seed = seed;
  const Scene scene = buildScene(scene_options);
  LidarModel model = lidarPreset("vlp16");
  model.range_noise = 0.02;
  model.dropout = 0.05;
  options.write_point_times = true;
  options.show_progress = false;
  options.scan = {true, seed};
  options.imu = imu;
  const fs::path out = tempDir(name);
  writeSequence(out, scene, model, options);
  return out;
}

std::string contents(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool sameFiles(const fs::path& a, const fs::path& b) {
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const fs::path other = b / fs::relative(e.path(), a);
    if (!fs::exists(other) || contents(e.path()) != contents(other)) return false;
  }
  return true;
}

TEST_F(SequenceWriter, LayoutIsReadable) {
  const fs::path out = generate("layout", 1, 4);
  const KittiSequence seq = listKittiSequence(out);
  ASSERT_EQ(seq.scans.size(), 4u);
  const Poses poses = readKittiPoses(out / "poses.txt");
  ASSERT_EQ(poses.size(), 4u);
  EXPECT_TRUE(poses[0].isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_NEAR(poses[1].translation().x(), 0.9, 1e-6);  // 9 m/s street, straight along x
  EXPECT_TRUE(readKittiCalibTr(out / "calib.txt").isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(readTimes(out / "times.txt"), (std::vector<double>{0.0, 0.1, 0.2, 0.3}));
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const Points pts = readKittiBin(seq.scans[k]);
    EXPECT_GT(pts.size(), 10000u);
    ASSERT_FALSE(seq.labels[k].empty());
    EXPECT_EQ(readSemanticKittiLabels(seq.labels[k]).size(), pts.size());
    EXPECT_EQ(readFloatBin(out / "point_times" / seq.scans[k].filename()).size(), pts.size());
  }
}

TEST_F(SequenceWriter, SameSeedSameBytesOtherSeedDiffers) {
  const fs::path a = generate("a", 42);
  const fs::path b = generate("b", 42);
  const fs::path c = generate("c", 43);
  EXPECT_TRUE(sameFiles(a, b));
  EXPECT_TRUE(sameFiles(b, a));
  EXPECT_NE(contents(a / "velodyne" / "000001.bin"), contents(c / "velodyne" / "000001.bin"));
}

TEST_F(SequenceWriter, AnImuWritesGravityAndChangesNothingElse) {
  const fs::path none = generate("none", 5, 3);
  EXPECT_FALSE(fs::exists(none / "gravity.txt"));
  const fs::path ins = generate("ins", 5, 3, imuPreset("ins"));
  EXPECT_TRUE(sameFiles(none, ins));  // the scans, poses and times of the seed, byte for byte
  const auto gravity = readGravityFile(ins / "gravity.txt");
  ASSERT_EQ(gravity.size(), 3u);
  for (const auto& g : gravity) {
    ASSERT_TRUE(g.has_value());
    EXPECT_NEAR(g->sigma, imuPreset("ins").sigma(), 1e-9);
    // No body motion here: the sensor is level, up is +z but for the sensor's errors.
    EXPECT_LT(std::acos(std::min(1.0, g->up.z())), 6.0 * g->sigma);
  }
  // Writing the same directory again without an IMU leaves no stale gravity.txt.
  SequenceOptions options;
  options.frames = 1;
  options.show_progress = false;
  writeSequence(ins, buildScene({}), lidarPreset("vlp16"), options);
  EXPECT_FALSE(fs::exists(ins / "gravity.txt"));
}

std::vector<std::string> lines(const fs::path& f) {
  std::vector<std::string> out;
  std::ifstream in(f);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// A recording at a third of the sensor's rate: sweeps 0, 3 and 6 of the full-rate sequence,
// scans, labels, point times, poses, times and attitude readings alike.
TEST_F(SequenceWriter, EveryNthSweepWritesTheFullRateSequencesFramesByteForByte) {
  const fs::path full = generate("full", 7, 7, imuPreset("ins"));
  const fs::path third = generate("third", 7, 3, imuPreset("ins"), 3);
  for (const char* dir : {"velodyne", "labels", "point_times"}) {
    std::size_t written = 0;
    for (const auto& e : fs::directory_iterator(third / dir)) {
      const std::size_t i = std::stoul(e.path().stem().string());
      char sweep[16];
      std::snprintf(sweep, sizeof(sweep), "%06zu", 3 * i);
      const fs::path same = full / dir / (sweep + e.path().extension().string());
      EXPECT_EQ(contents(e.path()), contents(same)) << e.path() << " against " << same;
      ++written;
    }
    EXPECT_EQ(written, 3u) << dir;
  }
  for (const char* file : {"poses.txt", "times.txt", "gravity.txt"}) {
    const std::vector<std::string> all = lines(full / file);
    ASSERT_EQ(all.size(), 7u) << file;
    EXPECT_EQ(lines(third / file), (std::vector<std::string>{all[0], all[3], all[6]})) << file;
  }
  SequenceOptions none;
  none.every = 0;
  none.show_progress = false;
  EXPECT_THROW(writeSequence(tempDir("none"), buildScene({}), lidarPreset("vlp16"), none),
               std::invalid_argument);
}

// With the realism's beam errors the sequence names its sensor instance's per-laser truth: one
// line per laser, the errors every scan was made with; exact sequences have none.
TEST_F(SequenceWriter, BeamsTxtHoldsTheSensorInstancesCalibrationErrors) {
  const Realism kitti = realismPreset("kitti");
  SequenceOptions options;
  options.frames = 1;
  options.show_progress = false;
  options.scan = {true, 4};
  options.scan.realism = &kitti;
  options.scan.sensor_seed = 9;
  SceneOptions scene_options;
  scene_options.frames = 1;
  const Scene scene = buildScene(scene_options);
  const LidarModel model = lidarPreset("vlp16");
  const fs::path out = tempDir("beams");
  writeSequence(out, scene, model, options);
  const BeamCalibration truth = drawBeamCalibration(kitti.beams, 16, 9);
  std::ifstream in(out / "beams.txt");
  std::size_t laser = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    double elevation = 0, elevation_error = 0, azimuth_error = 0, offset = 0, scale = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf", &elevation, &elevation_error,
                          &azimuth_error, &offset, &scale),
              5)
        << line;
    ASSERT_LT(laser, 16u);
    EXPECT_NEAR(elevation, model.elevations_deg[laser], 1e-4);
    EXPECT_NEAR(elevation_error, truth.elevation_error[laser] * 180.0 / M_PI, 1e-5);
    EXPECT_NEAR(azimuth_error, truth.azimuth_error[laser] * 180.0 / M_PI, 1e-5);
    EXPECT_NEAR(offset, truth.range_offset[laser], 1e-5);
    EXPECT_NEAR(scale, truth.range_scale[laser], 1e-6);
    ++laser;
  }
  EXPECT_EQ(laser, 16u);
  options.scan.realism = nullptr;  // the same directory, exact: no stale truth
  writeSequence(out, scene, model, options);
  EXPECT_FALSE(fs::exists(out / "beams.txt"));
}

TEST_F(SequenceWriter, TheRecordedHeightsReferenceDiffersOnlyInHeight) {
  const Scene scene = buildScene({});  // level at frame 0: its z is the map's z
  SequenceOptions options;
  options.frames = 3;
  options.show_progress = false;
  options.recorded_height_change = {0.0, 0.5, -1.25};
  const fs::path out = tempDir("recorded");
  writeSequence(out, scene, lidarPreset("vlp16"), options);
  const Poses road = readKittiPoses(out / "poses.txt");
  const Poses recorded = readKittiPoses(out / "poses_recorded_heights.txt");
  ASSERT_EQ(recorded.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(recorded[k].linear().isApprox(road[k].linear(), 1e-9)) << k;
    const Eigen::Vector3d moved = recorded[k].translation() - road[k].translation();
    EXPECT_NEAR(moved.z(), -options.recorded_height_change[k], 1e-6) << k;
    EXPECT_NEAR(moved.head<2>().norm(), 0.0, 1e-6) << k;
  }
  // Written again without one: no stale reference of another route.
  options.recorded_height_change.clear();
  writeSequence(out, scene, lidarPreset("vlp16"), options);
  EXPECT_FALSE(fs::exists(out / "poses_recorded_heights.txt"));
  options.recorded_height_change = {0.0};  // fewer than the frames
  EXPECT_THROW(writeSequence(out, scene, lidarPreset("vlp16"), options), std::invalid_argument);
}

TEST_F(SequenceWriter, UnwritableDirectoryThrows) {
  const Scene scene = buildScene({});
  SequenceOptions options;
  options.frames = 1;
  options.show_progress = false;
  EXPECT_ANY_THROW(
      writeSequence("/proc/socc_sim_cannot_write", scene, lidarPreset("vlp16"), options));
}

}  // namespace
}  // namespace socc::sim
