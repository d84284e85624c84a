#pragma once
// Private state of SemanticOccupancyMap, shared by the .cpp files that implement its parts
// (integration, chunk query, snapshot, exports, rendering).
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <vector>

#include "socc/map/ray_footprint.hpp"
#include "socc/map/semantic_block.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/map/semantic_voxel.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::map {

using Block = SemanticBlock;
using Grid = VoxelGrid<Block>;

/// The hit voxels of one partition of the scan (voxels whose block hashes to it). Partitions
/// own disjoint blocks, so they are aggregated and applied in parallel without locks.
struct HitPartition {
  tsl::robin_map<VoxelIndex, std::uint32_t, VoxelIndexHash> slot_of;
  std::vector<VoxelIndex> voxels;
  std::vector<FrameAggregate> frames;  // parallel to voxels
  std::vector<Block*> blocks;          // parallel to voxels
  std::vector<Block*> touched;         // blocks whose scan_mark this partition set
};

/// Per-scan working memory, kept between scans: reallocating (and page-faulting) megabytes
/// per scan would cost more than the integration itself.
struct ScanScratch {
  // Per point: map-frame position and voxel (hits), or max-range clipped end (misses only).
  enum class PointKind : std::uint8_t { kSkipped, kHit, kClipped };
  std::vector<PointKind> kind;
  std::vector<Eigen::Vector3d> position;
  std::vector<VoxelIndex> voxel;

  // A fixed count (not the thread count), so results do not depend on the machine.
  static constexpr std::size_t kHitPartitions = 4;
  std::array<HitPartition, kHitPartitions> partitions;

  tsl::robin_map<VoxelIndex, std::uint32_t, VoxelIndexHash> clipped_of;
  std::vector<Eigen::Vector3d> ray_ends;
  // Rays are split into this many fixed chunks, traversed in parallel into one footprint
  // each, and merged in chunk order (deterministic block order).
  static constexpr std::size_t kRayChunks = 4;
  std::array<RayFootprint, kRayChunks> footprints;
  std::vector<Block*> miss_blocks;  // grid block of each block of footprints[0]
};

/// A random non-zero map epoch (SemanticOccupancyMap::epoch).
std::int64_t newEpoch();

struct SemanticOccupancyMap::Impl {
  explicit Impl(const MapConfig& c) : config(c), behaviour(c), grid(c.voxel_size) {}

  MapConfig config;
  SemanticVoxelBehaviour behaviour;
  Grid grid;
  std::int64_t version = 0;
  std::int64_t epoch = newEpoch();
  std::int64_t num_observed = 0;  // kept up to date by integrate() so stats() is O(1)
  std::int64_t num_occupied = 0;

  tbb::task_arena arena{2};  // the machine's budget: two cores

  ScanScratch scratch;

  /// Recounts observed / occupied voxels (after loading).
  void recount();

  /// Calls f(index, log_odds, stats-or-null) for every observed voxel, blocks in key order.
  template <typename F>
  void forEachObserved(F&& f) const {
    std::vector<BlockKey> keys;
    keys.reserve(grid.numBlocks());
    for (const auto& [key, block] : grid.blocks()) keys.push_back(key);
    std::sort(keys.begin(), keys.end(), indexLess);
    for (const BlockKey& key : keys) {
      const Block& b = *grid.find(key);
      for (int local = 0; local < kBlockVoxels; ++local)
        if (b.observed[local]) f(voxelOf(key, local), b.log_odds[local], b.statsOf(local));
    }
  }
};

}  // namespace socc::map
