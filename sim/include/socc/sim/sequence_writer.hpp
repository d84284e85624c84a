#pragma once
// Writes a simulated sequence in the KITTI / SemanticKITTI layout:
//   velodyne/NNNNNN.bin  labels/NNNNNN.label (raw ids)  point_times/NNNNNN.bin (float32, s)
//   poses.txt (LiDAR-frame GT relative to frame 0, 3x4)  calib.txt (identity Tr)  times.txt
//   gravity.txt (with an attitude sensor: the up direction in the sensor frame,
//   socc/gravity_file.hpp)
//   poses_recorded_heights.txt (with recorded_height_change: poses.txt at a recording's heights,
//   the reference its published drift figures are scored against)
//   beams.txt (with realism's beam errors: the sensor instance's per-laser calibration errors)
#include <filesystem>
#include <vector>

#include "socc/sim/attitude_sensor.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/scene.hpp"

namespace socc::sim {

struct SequenceOptions {
  std::size_t frames = 100;   // frames written
  double frame_period = 0.1;  // [s] of the sensor's sweeps
  /// Every how many sweeps a frame is written: frame i is sweep i * every, as a recording of
  /// the sensor at 1 / every of its rate (e.g. 5: a 10 Hz LiDAR recorded at 2 Hz); the frames
  /// are those of the full-rate sequence, byte for byte. The scene must span
  /// sweepsSpanned(options) sweeps.
  std::size_t every = 1;
  bool write_point_times = false;
  bool show_progress = true;
  ScanOptions scan;
  /// The attitude sensor whose readings go to gravity.txt; none (no error term): no file.
  ImuErrors imu = {};
  /// Per frame [m]: the route's height minus the height its recording gives that frame (a
  /// --kitti-poses route on the road's heights, road_heights.hpp); empty: no such file.
  std::vector<double> recorded_height_change;
};

struct SequenceSummary {
  /// With noisy labels (realism "labels"): their mIoU [0, 1] against the exact ones and the
  /// number of classes it is taken over; 0 classes otherwise.
  double label_miou = 1.0;
  int label_classes = 0;
};

/// The sweeps from the first written frame to the last, both included.
inline std::size_t sweepsSpanned(const SequenceOptions& options) {
  return options.frames == 0 ? 0 : (options.frames - 1) * options.every + 1;
}

/// Throws std::runtime_error when the directory cannot be written.
SequenceSummary writeSequence(const std::filesystem::path& out, const Scene& scene,
                              const LidarModel& model, const SequenceOptions& options);

}  // namespace socc::sim
