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
  // A slot is kNoStats, or the index of the voxel's statistics in `stats` (below
  // kBlockVoxels: 9 bits) with, in the bits above, the voxel's miss class as last computed
  // (SemanticVoxelBehaviour::missClass; 0: not known yet). Misses use the class, so a ray
  // crossing a voxel with statistics need not read them (a cache miss each).
  static constexpr int kClassShift = 9;
  static constexpr std::uint16_t kIndexMask = (1u << kClassShift) - 1;
  static_assert(kBlockVoxels <= kIndexMask + 1, "statistics index must fit below the class");

  std::array<float, kBlockVoxels> log_odds{};
  std::array<std::uint16_t, kBlockVoxels> slot;
  std::bitset<kBlockVoxels> observed;  // unknown voxels are not observed
  // Scratch: voxel already updated by the current scan, as words (the misses skip them a word
  // at a time; layout of the ray footprint's VoxelMask).
  std::array<std::uint64_t, kBlockVoxels / 64> scan_mark{};
  bool in_scan = false;      // scratch: block is in the scan's touched list
  std::int64_t version = 0;  // map version of the last change (delta chunks)
  // Map version of the last change a chunk at the map's occupancy threshold (or above) can see:
  // a hit, or a miss on a voxel at or near that threshold. Rays clearing free space, most of a
  // scan's misses, leave it.
  std::int64_t occupied_version = 0;
  std::vector<VoxelStats> stats;
  std::vector<std::uint16_t> free_slots;

  SemanticBlock() { slot.fill(kNoStats); }

  const VoxelStats* statsOf(int local) const {
    return slot[local] == kNoStats ? nullptr : &stats[slot[local] & kIndexMask];
  }
  VoxelStats* statsOf(int local) {
    return slot[local] == kNoStats ? nullptr : &stats[slot[local] & kIndexMask];
  }

  /// Returns the voxel's statistics, creating a value-initialised entry (miss class not
  /// known) if it has none.
  VoxelStats& acquireStats(int local) {
    if (slot[local] != kNoStats) return stats[slot[local] & kIndexMask];
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
    free_slots.push_back(static_cast<std::uint16_t>(slot[local] & kIndexMask));
    slot[local] = kNoStats;
  }

  /// The cached miss class of a voxel with statistics (0: not known).
  int missClass(int local) const { return slot[local] >> kClassShift; }
  void setMissClass(int local, int miss_class) {
    slot[local] =
        static_cast<std::uint16_t>((slot[local] & kIndexMask) | (miss_class << kClassShift));
  }
  std::size_t memoryBytes() const {
    return sizeof(*this) + stats.capacity() * sizeof(VoxelStats) +
           free_slots.capacity() * sizeof(std::uint16_t);
  }
};

}  // namespace socc::map
