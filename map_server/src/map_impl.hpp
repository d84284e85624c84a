#pragma once
// Private state of SemanticOccupancyMap, shared by the .cpp files that implement its parts
// (integration, chunk query, snapshot, exports, rendering).
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <vector>

#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/map/semantic_voxel.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::map {

using Grid = VoxelGrid<VoxelStats>;
using Block = Grid::Block;

/// Per-scan working memory, kept between scans: reallocating (and page-faulting) megabytes
/// per scan would cost more than the integration itself.
struct ScanScratch {
  tsl::robin_map<VoxelIndex, std::uint32_t, IndexHash> hit_of;
  tsl::robin_map<VoxelIndex, std::uint32_t, IndexHash> clipped_of;
  std::vector<VoxelIndex> hit_voxels;
  std::vector<FrameAggregate> hits;  // parallel to hit_voxels
  std::vector<Eigen::Vector3d> ray_ends;
  // Ray batches in flight in the traversal pipeline (small, so they stay in cache).
  static constexpr std::size_t kRayBatches = 4;
  std::array<std::vector<VoxelIndex>, kRayBatches> ray_voxels;
  std::array<std::array<std::vector<VoxelIndex>, 2>, kRayBatches> ray_tmp;  // current, previous
  std::vector<Block*> touched;
};

struct SemanticOccupancyMap::Impl {
  explicit Impl(const MapConfig& c) : config(c), behaviour(c) {}

  MapConfig config;
  SemanticVoxelBehaviour behaviour;
  Grid grid;
  std::int64_t version = 0;
  std::int64_t num_observed = 0;  // kept up to date by integrate() so stats() is O(1)
  std::int64_t num_occupied = 0;

  tbb::task_arena arena{2};  // the machine's budget: two cores

  ScanScratch scratch;

  double voxelSize() const { return config.voxel_size; }
  Eigen::Vector3d centre(const VoxelIndex& v) const {
    return (v.cast<double>().array() + 0.5).matrix() * config.voxel_size;
  }
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
