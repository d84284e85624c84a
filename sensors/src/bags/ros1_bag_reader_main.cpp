// socc-ros1-bag-reader FILE: the child process of the ROS 1 bag reader (ros1_bag_reader.cpp),
// started by posix_spawn with its frame pipe on descriptor 3 and the value socket on 4
// (ForkedReader). A program of its own, not a fork of the caller: a fresh process inherits no
// lock that another thread of the caller held (docs/sensors_bags.md).
#include <unistd.h>

#include <cstdio>

#include "bags/forked_reader.hpp"
#include "bags/ros1_bag_child.hpp"

int main(int argc, char** argv) {
  using socc::sensors::bags::ForkedReader;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s BAG (started by socc's ROS 1 bag reader)\n", argv[0]);
    return 2;
  }
  socc::sensors::bags::FrameWriter writer(ForkedReader::kChildFramesFd,
                                          ForkedReader::kChildValuesFd);
  const std::string file = argv[1];
  socc::sensors::bags::runChildWork(
      [&file](socc::sensors::bags::FrameWriter& out) {
        socc::sensors::bags::readRos1BagInChild(file, out);
      },
      writer);
  // As a forked child: no destructors of rosbag_storage's globals, no leak report at exit.
  ::_exit(0);
}
