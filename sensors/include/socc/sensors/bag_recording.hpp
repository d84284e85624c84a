#pragma once
// Bags (ROS 1 .bag, ROS 2 .db3 / folder, .mcap) as scan streams: sensor_msgs/PointCloud2
// topics directly, packet topics (velodyne_msgs/VelodyneScan, pandar_msgs/PandarScan, Ouster
// packets) through makeDecoder. openRecording (recording.hpp) dispatches here.
#include <filesystem>
#include <memory>

#include "socc/sensors/recording.hpp"

namespace socc::sensors {

/// True when file looks like a bag this reader handles (by extension / folder layout).
bool isBag(const std::filesystem::path& file);

std::unique_ptr<ScanStream> openBag(const std::filesystem::path& file,
                                    const RecordingOptions& options);

}  // namespace socc::sensors
