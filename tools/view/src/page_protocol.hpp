#pragma once
// What socc-view's page receives on its WebSocket (/ws), all little-endian (docs/view.md):
// * text: JSON objects with "type": "hello" (voxel size, block edge, class names and colours,
//   tracking state names), "reset" (a new map epoch: drop every voxel and robot), "stats" (the map
//   server's map_stats_t), "robots" (per robot: pose, tracking state, the trajectory points
//   after those already sent).
// * binary, first byte the kind: kBlocks (blocks whose voxels replace what the page holds)
//   and kScan (one robot's latest scan, map frame).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "view_model.hpp"

namespace socc::view::page {

inline constexpr std::uint8_t kBlocks = 1;  // u8 kind, u8 0 x3, u32 n; per block: i32 x3
                                            // key, u16 count, count x (u16 local, u8 occ, u8 label)
inline constexpr std::uint8_t kScan = 2;    // u8 kind, u8 id length, id, u32 n, f32 x3 origin,
                                            // n x i16 x3: (point - origin) / kScanStep
inline constexpr float kScanStep = 0.02f;   // [m]: +-655 m around the robot in 6 bytes a point

std::string hello(const ViewModel& model);
std::string reset();
std::string stats(const ViewModel& model);
/// sent_points: per robot id, trajectory points the page already has (updated).
std::string robots(const ViewModel& model, std::map<std::string, std::size_t>& sent_points);

/// Appends the blocks (missing ones as empty) to a kBlocks message, up to max_bytes (at least
/// one block); returns how many keys it took.
std::size_t blocks(const ViewModel& model, const std::vector<BlockKey>& keys, std::size_t first,
                   std::size_t max_bytes, std::vector<std::uint8_t>& out);
std::vector<std::uint8_t> scan(const RobotView& robot);

}  // namespace socc::view::page
