#pragma once
// The ROS 1 bag reader's child side (rosbag_storage), run in the helper program
// socc-ros1-bag-reader that Ros1BagReader starts (ros1_bag_reader.cpp).
#include <string>

#include "bags/forked_reader.hpp"

namespace socc::sensors::bags {

/// Opens the bag, sends its topics and a topics-end frame, waits for the topic to read (an index
/// into the topics; any larger value: all), then sends its messages in record-time order.
/// Throws what rosbag_storage throws at opening (as std::runtime_error).
void readRos1BagInChild(const std::string& file, FrameWriter& out);

}  // namespace socc::sensors::bags
