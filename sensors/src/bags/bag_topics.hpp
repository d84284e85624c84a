#pragma once
// Which topic of a bag to read: the one asked for, or the only LiDAR topic (a PointCloud2 or a
// packet topic in a serialization socc decodes). Errors list the bag's topics.
#include <filesystem>
#include <string>

#include "bags/bag_reader.hpp"

namespace socc::sensors::bags {

/// The index in reader.topics() of the topic to read; throws std::runtime_error naming file
/// and listing the topics when requested is absent or unsupported, or when requested is empty
/// and there is not exactly one LiDAR topic (Ouster topics named *imu* do not count).
std::size_t chooseTopic(const BagReader& reader, const std::string& requested,
                        const std::filesystem::path& file);

}  // namespace socc::sensors::bags
