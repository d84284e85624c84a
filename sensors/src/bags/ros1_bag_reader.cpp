#include "bags/bag_reader.hpp"
namespace socc::sensors::bags {
std::unique_ptr<BagReader> openRos1Bag(const std::filesystem::path& file) {
  throw std::runtime_error(file.string() + ": ROS 1 not yet");
}
}  // namespace socc::sensors::bags
