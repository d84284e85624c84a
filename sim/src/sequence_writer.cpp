#include "socc/sim/sequence_writer.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "socc/gravity_file.hpp"
#include "socc/kitti_io.hpp"
#include "socc/progress_bar.hpp"
#include "socc/sim/beam_calibration.hpp"
#include "socc/sim/label_noise.hpp"

namespace socc::sim {
namespace fs = std::filesystem;

namespace {

std::string frameName(std::size_t k, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu%s", k, ext);
  return name;
}

void writeText(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

// The sensor instance's per-laser calibration errors, the truth an estimate of them (odom_client's
// range_calibration.txt) is compared with; none (a stale one removed) without such errors.
void writeBeamTruth(const fs::path& file, const LidarModel& model, const ScanOptions& scan) {
  if (scan.realism == nullptr || !scan.realism->beams.any()) {
    fs::remove(file);
    return;
  }
  constexpr double kDegreesPerRadian = 180.0 / M_PI;
  const BeamCalibration c = drawBeamCalibration(scan.realism->beams, model.elevations_deg.size(),
                                                scan.sensor_seed.value_or(scan.seed));
  std::string text =
      "# socc-sim sensor instance: per-laser calibration errors (angles true minus nominal;\n"
      "# reported range = true range * (1 + range_scale) + range_offset)\n"
      "# nominal_elevation_deg elevation_error_deg azimuth_error_deg range_offset_m range_scale\n";
  for (std::size_t b = 0; b < model.elevations_deg.size(); ++b) {
    char line[160];
    std::snprintf(line, sizeof(line), "%.4f %.5f %.5f %.5f %.6f\n", model.elevations_deg[b],
                  c.elevation_error[b] * kDegreesPerRadian, c.azimuth_error[b] * kDegreesPerRadian,
                  c.range_offset[b], c.range_scale[b]);
    text += line;
  }
  writeText(file, text);
}

}  // namespace

SequenceSummary writeSequence(const fs::path& out, const Scene& scene, const LidarModel& model,
                              const SequenceOptions& options) {
  if (options.every == 0) throw std::invalid_argument("writeSequence: every must be >= 1");
  const std::vector<double>& change = options.recorded_height_change;
  if (!change.empty() && change.size() < sweepsSpanned(options))
    throw std::invalid_argument("writeSequence: a recorded height change per sweep is needed");
  for (const char* dir : {"velodyne", "labels"}) fs::create_directories(out / dir);
  if (options.write_point_times) fs::create_directories(out / "point_times");

  Poses poses;
  Poses recorded;
  std::string times;
  const Eigen::Isometry3d first_inverse = scene.trajectory.poseAt(0.0).inverse();
  LabelScore labels;
  std::optional<AttitudeSensor> imu;
  if (options.imu.any())
    imu.emplace(options.imu, options.scan.seed,
                options.scan.sensor_seed.value_or(options.scan.seed));
  std::vector<std::optional<GravityReference>> gravity;
  std::size_t imu_sweep = 0;  // the next sweep the attitude sensor reads
  ProgressBar progress("socc-sim", options.frames, options.show_progress);
  for (std::size_t i = 0; i < options.frames; ++i) {
    const std::size_t k = i * options.every;  // the sweep
    const double t = options.frame_period * static_cast<double>(k);
    // The attitude sensor reads the sweeps not written too, so that its readings of the
    // written ones are those of the full-rate sequence.
    for (; imu && imu_sweep < k; ++imu_sweep) {
      const double ts = options.frame_period * static_cast<double>(imu_sweep);
      imu->measure(scene.trajectory.poseAt(ts).linear(), ts);
    }
    const SimulatedScan scan = simulateScan(scene, model, t, k, options.scan);
    writeKittiBin(out / "velodyne" / frameName(i, ".bin"), scan.points, &scan.reflectance);
    writeSemanticKittiLabels(out / "labels" / frameName(i, ".label"), scan.labels);
    if (!scan.exact_labels.empty()) labels.add(scan.exact_labels, scan.labels);
    if (options.write_point_times) {
      std::ofstream f(out / "point_times" / frameName(i, ".bin"), std::ios::binary);
      f.write(reinterpret_cast<const char*>(scan.times.data()),
              static_cast<std::streamsize>(scan.times.size() * sizeof(float)));
      if (!f) throw std::runtime_error((out / "point_times").string() + ": cannot write");
    }
    const Eigen::Isometry3d pose = scene.trajectory.poseAt(t);
    // KITTI convention: poses relative to the first frame.
    poses.push_back(first_inverse * pose);
    if (!change.empty())
      recorded.push_back(first_inverse * Eigen::Translation3d(0.0, 0.0, -change[k]) * pose);
    // The up direction in the sensor frame at the pose's time, independent of frame 0's tilt.
    if (imu) gravity.push_back(imu->measure(pose.linear(), t));
    imu_sweep = k + 1;
    char line[32];
    std::snprintf(line, sizeof(line), "%e\n", t);
    times += line;
    progress.tick(std::to_string(scan.points.size()) + " pts");
  }
  progress.finish();
  writeKittiPoses(out / "poses.txt", poses);
  if (!change.empty())
    writeKittiPoses(out / "poses_recorded_heights.txt", recorded);
  else
    fs::remove(out / "poses_recorded_heights.txt");  // a stale one would belong to another route
  writeText(out / "times.txt", times);
  writeText(out / "calib.txt", "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  writeBeamTruth(out / "beams.txt", model, options.scan);
  if (imu)
    writeGravityFile(out / "gravity.txt", gravity);
  else
    fs::remove(out / "gravity.txt");  // a stale one would belong to another sequence
  return {labels.meanIou(), labels.classesPresent()};
}

}  // namespace socc::sim
