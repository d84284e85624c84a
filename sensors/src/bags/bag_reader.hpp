#pragma once
// One interface over the bag containers: ROS 2 .db3 (SQLite), MCAP, ROS 1 .bag. A reader lists
// the topics, then yields the serialized messages of the selected topic in the order they are
// stored (ROS 1: in record-time order, as rosbag::View gives them), with the recorder's receive
// time. Readers throw std::runtime_error naming the file
// when it cannot be opened at all; damage found later (a truncated or corrupted record or
// chunk) ends or skips that part, is counted, and is told by problems().
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bags/ros_messages.hpp"

namespace socc::sensors::bags {

struct TopicInfo {
  std::string name;
  std::string type;  // as stored: "sensor_msgs/msg/PointCloud2" or "sensor_msgs/PointCloud2"
  std::string serialization;         // as stored: "cdr", "ros1", ...
  std::optional<Encoding> encoding;  // empty: a serialization socc does not decode
  std::uint64_t messages = 0;        // as far as the container tells (0: unknown)
};

struct BagMessage {
  std::size_t topic = 0;           // index into topics()
  std::int64_t stamp_ns = 0;       // the recorder's receive time (log time)
  std::vector<std::uint8_t> data;  // the serialized message
};

class BagReader {
 public:
  virtual ~BagReader() = default;
  virtual const std::vector<TopicInfo>& topics() const = 0;
  /// From now on next() yields only messages of topics()[topic].
  virtual void select(std::size_t topic) = 0;
  virtual std::optional<BagMessage> next() = 0;
  /// Counted damage so far, one line per kind; empty when none.
  virtual std::string problems() const = 0;
};

/// ROS 2 bag: a .db3 file, or a folder with metadata.yaml and .db3 / .mcap files.
std::unique_ptr<BagReader> openRos2Bag(const std::filesystem::path& path);
std::unique_ptr<BagReader> openDb3(const std::filesystem::path& file);
std::unique_ptr<BagReader> openMcap(const std::filesystem::path& file);
std::unique_ptr<BagReader> openRos1Bag(const std::filesystem::path& file);

/// A file named .bag, .db3 or .mcap (any case).
bool hasBagExtension(const std::filesystem::path& file);

/// By extension / folder layout; throws when path is none of the above.
std::unique_ptr<BagReader> openBagReader(const std::filesystem::path& path);

/// "  /points  sensor_msgs/msg/PointCloud2  (120 messages)" lines, for error messages.
std::string describeTopics(const std::vector<TopicInfo>& topics);

}  // namespace socc::sensors::bags
