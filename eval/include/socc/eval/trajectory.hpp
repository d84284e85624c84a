#pragma once
// Loading trajectories to evaluate: KITTI (3x4 per line) or TUM ("t x y z qx qy qz qw"),
// optionally converting KITTI camera-frame ground truth to the LiDAR frame.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc::eval {

enum class TrajectoryFormat { kAuto, kKitti, kTum };

/// "auto", "kitti" or "tum"; throws std::invalid_argument otherwise.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

using socc::Trajectory;  // stamps from TUM files; seqs stay empty

/// kAuto decides from the first data line (12 numbers: KITTI, 8: TUM). With a calib file the
/// poses are taken to be KITTI camera-frame poses and moved to the LiDAR frame
/// (T_lidar = Tr^-1 T_cam Tr). Throws std::runtime_error naming the file on bad input.
Trajectory loadTrajectory(const std::filesystem::path& file, TrajectoryFormat format,
                          const std::optional<std::filesystem::path>& calib = std::nullopt);

}  // namespace socc::eval
