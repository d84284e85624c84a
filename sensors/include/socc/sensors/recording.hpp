#pragma once
// Opens any supported recording as a stream of scans: pcap captures of LiDAR packets, ROS 1
// bags (.bag), ROS 2 bags (.db3 or its folder with metadata.yaml, .mcap). Every program that
// reads recordings goes through here.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "socc/sensors/sensor_config.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

struct RecordingOptions {
  SensorConfig sensor;     // for packet recordings (pcap, packet topics of bags)
  std::string topic;       // bags: the topic to read; empty: the only LiDAR topic, if one
  std::uint16_t port = 0;  // pcap: UDP destination port; 0: the sensor's default ports
};

std::unique_ptr<ScanStream> openRecording(const std::filesystem::path& file,
                                          const RecordingOptions& options);

}  // namespace socc::sensors
