#pragma once
// The map's block of kBlockVoxels voxels (the cell type of VoxelGrid): occupancy for every
// voxel, statistics for those that were hit, and the per-scan marks the integrator uses.
#include <array>
#include <bitset>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "socc/map/semantic_voxel.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::map {

inline constexpr std::uint16_t kNoStats = 0xFFFF;

/// One block. Every voxel pays only for its log-odds and a 16-bit slot; the (large)
/// statistics live in a per-block pool and exist only for voxels that have them.
struct SemanticBlock {
  std::array<float, kBlockVoxels> log_odds{};
  std::array<std::uint16_t, kBlockVoxels> slot;
  std::bitset<kBlockVoxels> observed;   // unknown voxels are not observed
  std::bitset<kBlockVoxels> scan_mark;  // scratch: voxel already updated by the current scan
  bool in_scan = false;                 // scratch: block is in the scan's touched list
  std::int64_t version = 0;             // map version of the last change (delta chunks)
  std::vector<VoxelStats> stats;
  std::vector<std::uint16_t> free_slots;

  SemanticBlock() { slot.fill(kNoStats); }

  const VoxelStats* statsOf(int local) const {
    return slot[local] == kNoStats ? nullptr : &stats[slot[local]];
  }
  VoxelStats* statsOf(int local) { return slot[local] == kNoStats ? nullptr : &stats[slot[local]]; }

  /// Returns the voxel's statistics, creating a value-initialised entry if it has none.
  VoxelStats& acquireStats(int local) {
    if (slot[local] != kNoStats) return stats[slot[local]];
    if (!free_slots.empty()) {
      slot[local] = free_slots.back();
      free_slots.pop_back();
      stats[slot[local]] = VoxelStats{};
    } else {
      slot[local] = static_cast<std::uint16_t>(stats.size());
      stats.emplace_back();
    }
    return stats[slot[local]];
  }
  void releaseStats(int local) {
    if (slot[local] == kNoStats) return;
    free_slots.push_back(slot[local]);
    slot[local] = kNoStats;
  }
  std::size_t memoryBytes() const {
    return sizeof(*this) + stats.capacity() * sizeof(VoxelStats) +
           free_slots.capacity() * sizeof(std::uint16_t);
  }
};

}  // namespace socc::map
