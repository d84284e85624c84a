#pragma once
// TEMPORARY, test-only readers for the Ouster / Hesai decoder tests, until the library's own
// pcap source (velodyne worktree) and ROS 2 bag reader (bags worktree) are merged; then these
// tests switch to them and this file goes. Deliberately minimal: no damage handling beyond
// throwing, since they only read the shared reference recordings.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "socc/sensors/packet.hpp"

namespace socc::sensors::test_io {

/// UDP payloads to destination port `port` of a classic pcap file, IPv4 fragments reassembled.
std::vector<Packet> readPcapUdp(const std::filesystem::path& file, std::uint16_t port);

/// The packets of every pandar_msgs/PandarScan message of a ROS 2 .db3 bag, one vector per
/// message in time order (CDR layout: raw_sensors/README.md).
std::vector<std::vector<Packet>> readDb3PandarScans(const std::filesystem::path& file);

/// x, y, z of a binary PCD file whose fields are x y z float32.
std::vector<Eigen::Vector3f> readBinaryPcdXyz(const std::filesystem::path& file);

}  // namespace socc::sensors::test_io
