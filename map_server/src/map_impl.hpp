#pragma once
// Private state of SemanticOccupancyMap, shared by the .cpp files that implement its parts
// (integration, chunk query, snapshot, exports, rendering).
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <memory>
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
/// Voxel -> slot (0, 1, ... in order of insertion) for one scan. Two levels, for locality: a
/// small open-addressing table of the scan's blocks, each with a table of its 512 voxels'
/// slots. Entries of earlier scans are told apart by a generation stamp, so clear() is O(1).
class VoxelSlots {
 public:
  void clear() {
    size_ = 0;
    tables_used_ = 0;
    last_slots_ = nullptr;
    if (++generation_ == 0) {  // stamps wrapped: forget every entry for real
      std::fill(blocks_.begin(), blocks_.end(), BlockEntry{});
      generation_ = 1;
    }
  }

  /// The voxel's slot; a new voxel gets the next slot (inserted = true).
  std::uint32_t find(const VoxelIndex& v, bool& inserted) {
    const BlockKey b = blockOf(v);
    if (last_slots_ == nullptr || b != last_block_) {  // runs mostly stay in one block
      last_block_ = b;
      last_slots_ = slotsOf(b);
    }
    std::uint32_t& slot = last_slots_[localOf(v)];
    inserted = slot == kNone;
    if (inserted) slot = size_++;
    return slot;
  }

 private:
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  struct BlockEntry {
    BlockKey key = BlockKey::Zero();
    std::uint32_t table = 0;
    std::uint32_t generation = 0;  // 0: never used
  };
  static std::size_t indexOf(const BlockKey& b, std::size_t mask) {
    // The spatial hash's low bits follow the coordinates' low bits: mix them first.
    return static_cast<std::size_t>((VoxelIndexHash{}(b)*0x9E3779B97F4A7C15ull) >> 32) & mask;
  }
  std::uint32_t* slotsOf(const BlockKey& b) {
    if (2 * (tables_used_ + 1) > blocks_.size()) grow();
    const std::size_t mask = blocks_.size() - 1;
    std::size_t i = indexOf(b, mask);
    while (blocks_[i].generation == generation_) {
      if (blocks_[i].key == b) return &slots_[std::size_t{blocks_[i].table} * kBlockVoxels];
      i = (i + 1) & mask;
    }
    const std::uint32_t table = tables_used_++;
    blocks_[i] = {b, table, generation_};
    if (slots_.size() < std::size_t{tables_used_} * kBlockVoxels)
      slots_.resize(std::size_t{tables_used_} * kBlockVoxels);
    std::uint32_t* slots = &slots_[std::size_t{table} * kBlockVoxels];
    std::fill(slots, slots + kBlockVoxels, kNone);
    return slots;
  }
  void grow() {
    std::vector<BlockEntry> old;
    old.swap(blocks_);
    blocks_.assign(std::max<std::size_t>(256, 2 * old.size()), BlockEntry{});
    const std::size_t mask = blocks_.size() - 1;
    for (const BlockEntry& e : old) {
      if (e.generation != generation_) continue;
      std::size_t i = indexOf(e.key, mask);
      while (blocks_[i].generation == generation_) i = (i + 1) & mask;
      blocks_[i] = e;
    }
  }
  std::vector<BlockEntry> blocks_;
  std::vector<std::uint32_t> slots_;  // kBlockVoxels per block table
  BlockKey last_block_ = BlockKey::Zero();
  std::uint32_t* last_slots_ = nullptr;  // last_block_'s table (valid until slots_ grows)
  std::uint32_t size_ = 0;
  std::uint32_t tables_used_ = 0;
  std::uint32_t generation_ = 1;
};

/// A point that hit a voxel: map-frame position, voxel, index in the cloud (its label).
struct HitPoint {
  Eigen::Vector3d position;
  VoxelIndex voxel;
  std::uint32_t point;
};

struct HitPartition {
  // The hit points of point range r, in order: hits[r * kPointRange, + hit_count[r]). One
  // buffer, allocated (not initialised) for every point: a range's share never outgrows its
  // region, and only the pages written are ever touched.
  std::unique_ptr<HitPoint[]> hits;
  std::size_t hit_capacity = 0;  // in points
  std::vector<std::uint32_t> hit_count;
  VoxelSlots slot_of;
  std::vector<VoxelIndex> voxels;
  // Parallel to voxels (entry i is voxel i's; entries past voxels.size() are spare: kept
  // between scans and reset when taken, cheaper than constructing 216 bytes each time).
  std::vector<FrameAggregate> frames;
  std::vector<Block*> blocks;   // parallel to voxels
  std::vector<Block*> touched;  // blocks whose scan_mark this partition set
};

/// Per-scan working memory, kept between scans: reallocating (and page-faulting) megabytes
/// per scan would cost more than the integration itself.
struct ScanScratch {
  // Per point range: the max-range clipped ends of its points beyond max range (misses
  // only), in point order.
  struct ClippedPoint {
    Eigen::Vector3d position;
    VoxelIndex voxel;
  };
  std::vector<std::vector<ClippedPoint>> clipped;

  // Points are classified in fixed ranges, which list their hit points per partition: a
  // partition reads its points in point order. Fixed counts (not the thread count), so
  // results do not depend on the machine.
  static constexpr std::size_t kPointRange = 4096;
  static constexpr std::size_t kHitPartitions = 4;
  std::array<HitPartition, kHitPartitions> partitions;

  tsl::robin_map<VoxelIndex, std::uint32_t, VoxelIndexHash> clipped_of;
  std::vector<Eigen::Vector3d> ray_ends;
  // Rays are split into fixed chunks, traversed in parallel; each thread of the arena marks
  // into its own footprint, and the footprints are merged into footprints[0]. A footprint is
  // a set (and lists its blocks in key order), so the result does not depend on which
  // thread walked which ray.
  static constexpr std::size_t kRayChunks = 4;
  std::vector<RayFootprint> footprints;  // one per arena thread
  std::vector<Block*> miss_blocks;       // grid block of each block of footprints[0]
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

  // The machine's budget: two cores. Mutable: const queries run their parallel parts in it too.
  mutable tbb::task_arena arena{2};

  ScanScratch scratch;

  /// Recounts observed / occupied voxels (after loading).
  void recount();

  /// SemanticOccupancyMap::integrate, changing only within's blocks when within is not null,
  /// and listing its footprint in *footprint when that is not null.
  IntegrationResult integrate(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud,
                              const BlockRegion* within, std::vector<BlockKey>* footprint);
  /// SemanticOccupancyMap::footprint.
  std::vector<BlockKey> footprint(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud);

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
