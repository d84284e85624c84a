#pragma once
// Seed inputs of the bag harnesses (fuzz_bag_containers, fuzz_bag_messages): a two-point
// PointCloud2 in CDR and ROS 1 serialization, packet messages, and the smallest valid .db3,
// MCAP (plain and chunked) and ROS 1 bag holding it. Written from the formats' documentation.
#include <filesystem>
#include <string>
#include <vector>

namespace socc::fuzz {

struct BagSeed {
  std::string harness;
  std::string name;
  std::string content;  // selector byte included
};

/// scratch: a folder for the SQLite database built on the way.
std::vector<BagSeed> bagSeeds(const std::filesystem::path& scratch);

}  // namespace socc::fuzz
