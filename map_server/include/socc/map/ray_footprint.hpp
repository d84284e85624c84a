#pragma once
// The voxels a group of rays passed through, as one 512-bit mask per 8^3 block. Marking is
// idempotent, so rays sharing voxels near the sensor need no deduplication pass, and each
// voxel is later missed exactly once however many rays crossed it.
#include <tsl/robin_map.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

#include "socc/map/ray_traversal.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::map {

using VoxelMask = std::array<std::uint64_t, kBlockVoxels / 64>;

class RayFootprint {
 public:
  /// Starts an empty footprint for rays whose voxels all lie in the box [lo, hi]. A small
  /// box is covered by a dense bit grid (one bit per voxel, x-major, z fastest: a step along
  /// a ray is a fixed index stride, so markRays walks several rays at once with SIMD); a
  /// large one (fine voxels, long range) by a hash map of block masks. The grid is sized
  /// when the first voxel is marked: a footprint nobody marks costs nothing.
  void reset(const VoxelIndex& lo, const VoxelIndex& hi) {
    slot_of_.clear();
    keys_.clear();
    masks_.clear();
    cache_.fill(CacheEntry{});
    // Block-aligned box; each row of z a whole number of bytes, so a byte of a row is one
    // block's 8 voxels along z, and the 8 rows of a block's x slice are whole words.
    for (int i = 0; i < 3; ++i) grid_lo_[i] = lo[i] & ~(kBlockDim - 1);  // floor to a block
    const Eigen::Array3d blocks = ((hi - grid_lo_).cast<double>().array() + 1.0) / kBlockDim;
    const Eigen::Array3d dims = blocks.ceil() * kBlockDim;
    dense_ = dims.prod() <= static_cast<double>(kMaxDenseBits);
    if (!dense_) return;
    nx_ = static_cast<int>(dims.x());
    ny_ = static_cast<int>(dims.y());
    nz_ = static_cast<int>(dims.z());
    if (dirty_) std::fill(grid_.begin(), grid_.end(), 0);  // marked but never finished
    dirty_ = false;
  }

  bool dense() const { return dense_; }

  /// Ends marking: lists the touched blocks with their masks, in key order (indexLess), for
  /// numBlocks() / key() / mask() / merge().
  void finish() {
    if (dense_) {
      denseToBlocks();
    } else {  // hash mode: sort the list (indices of slot_of_ are rebuilt)
      std::vector<std::uint32_t> order(keys_.size());
      std::iota(order.begin(), order.end(), 0u);
      std::sort(order.begin(), order.end(),
                [&](std::uint32_t a, std::uint32_t b) { return indexLess(keys_[a], keys_[b]); });
      std::vector<BlockKey> keys(keys_.size());
      std::vector<VoxelMask> masks(masks_.size());
      slot_of_.clear();
      for (std::size_t i = 0; i < order.size(); ++i) {
        keys[i] = keys_[order[i]];
        masks[i] = masks_[order[i]];
        slot_of_.emplace(keys[i], static_cast<std::uint32_t>(i));
      }
      keys_.swap(keys);
      masks_.swap(masks);
      cache_.fill(CacheEntry{});
    }
  }

  /// Marks the voxels of one ray, walked by forEachVoxelOnRay. In hash mode the current
  /// block's mask is kept in the marker: a ray changes block only every few steps.
  class Marker {
   public:
    explicit Marker(RayFootprint& footprint) : footprint_(footprint) {
      if (footprint.dense_) footprint.useGrid();
    }
    void operator()(const VoxelIndex& v) {
      if (footprint_.dense_) {  // the same every step: predicted
        footprint_.markDense(footprint_.denseIndex(v));
        return;
      }
      const BlockKey key = blockOf(v);
      const int local = localOf(v);
      if (mask_ == nullptr || key != key_) enter(key);
      mask_[local >> 6] |= std::uint64_t{1} << (local & 63);
    }

   private:
    __attribute__((noinline)) void enter(const BlockKey& key) {  // keeps the hot loop small
      key_ = key;
      mask_ = footprint_.maskOf(key).data();
    }
    RayFootprint& footprint_;
    BlockKey key_ = BlockKey::Zero();
    std::uint64_t* mask_ = nullptr;
  };

  /// Marks the voxels of the rays from origin to ends[0..n) (the same voxels as a Marker
  /// given forEachVoxelOnRay of each). In dense mode the rays are walked in SIMD lanes, six
  /// (SSE2) or eight (AVX2, when the CPU has it) at a time (ray_traversal.cpp).
  void markRays(const Eigen::Vector3d& origin, const Eigen::Vector3d* ends, std::size_t n,
                double voxel_size);

  /// Before finish(): adds other's marks (both reset to the same box) and empties other.
  void absorb(RayFootprint& other);

  /// After finish(): adds other's voxels; blocks new to this footprint are appended in
  /// other's order.
  void merge(const RayFootprint& other) {
    for (std::size_t i = 0; i < other.keys_.size(); ++i) {
      VoxelMask& mask = maskOf(other.keys_[i]);
      for (std::size_t w = 0; w < mask.size(); ++w) mask[w] |= other.masks_[i][w];
    }
  }

  std::size_t numBlocks() const { return keys_.size(); }
  const BlockKey& key(std::size_t i) const { return keys_[i]; }
  const VoxelMask& mask(std::size_t i) const { return masks_[i]; }

 private:
  std::size_t denseIndex(const VoxelIndex& v) const {
    return (static_cast<std::size_t>(v.x() - grid_lo_.x()) * static_cast<std::size_t>(ny_) +
            static_cast<std::size_t>(v.y() - grid_lo_.y())) *
               static_cast<std::size_t>(nz_) +
           static_cast<std::size_t>(v.z() - grid_lo_.z());
  }
  void markDense(std::size_t i) { grid_[i >> 6] |= std::uint64_t{1} << (i & 63); }

  /// Marks will follow: sizes the (all-zero) grid for the box.
  void useGrid() {
    dirty_ = true;
    const std::size_t bits = static_cast<std::size_t>(nx_) * ny_ * nz_;
    if (grid_.size() < bits / 64) grid_.resize(bits / 64);  // bits: a multiple of 512
  }

  /// Copies the dense grid's set bits into block masks (key order) and clears the grid.
  void denseToBlocks() {
    if (!dirty_) return;  // nothing marked
    dirty_ = false;
    // Row (x, y) holds z bytes (z_bytes of them); the rows (x, by * 8 .. by * 8 + 7) are the
    // z_bytes words from word (x * ny / 8 + by) * z_bytes: block (bx, by, b)'s slice at x.
    const std::size_t z_bytes = static_cast<std::size_t>(nz_) / 8;
    const std::size_t strips_y = static_cast<std::size_t>(ny_) / kBlockDim;
    const BlockKey first = blockOf(grid_lo_);
    column_.resize(z_bytes);
    for (int bx = 0; bx < nx_ / kBlockDim; ++bx)
      for (std::size_t by = 0; by < strips_y; ++by) {
        bool any = false;
        for (int xl = 0; xl < kBlockDim; ++xl) {
          const std::size_t x = static_cast<std::size_t>(bx * kBlockDim + xl);
          std::uint64_t* strip = &grid_[(x * strips_y + by) * z_bytes];
          std::uint64_t bits = 0;
          for (std::size_t w = 0; w < z_bytes; ++w) bits |= strip[w];
          if (bits == 0) continue;
          if (!any) std::fill(column_.begin(), column_.end(), VoxelMask{});
          any = true;
          for (std::size_t yl = 0, k = 0; yl < kBlockDim; ++yl)
            for (std::size_t b = 0; b < z_bytes; ++b, ++k) {  // byte k of the strip
              const std::uint64_t byte = (strip[k >> 3] >> (8 * (k & 7))) & 0xFFu;
              column_[b][static_cast<std::size_t>(xl)] |= byte << (kBlockDim * yl);
            }
          std::fill(strip, strip + z_bytes, 0);
        }
        if (!any) continue;
        for (std::size_t b = 0; b < z_bytes; ++b) {
          const VoxelMask& m = column_[b];
          if (std::any_of(m.begin(), m.end(), [](std::uint64_t w) { return w != 0; })) {
            keys_.push_back(first + BlockKey(bx, static_cast<int>(by), static_cast<int>(b)));
            masks_.push_back(m);
          }
        }
      }
    // Indexed too, for merge().
    for (std::size_t i = 0; i < keys_.size(); ++i)
      slot_of_.emplace(keys_[i], static_cast<std::uint32_t>(i));
  }

  /// The block's mask, created empty if needed; valid until the next block is added.
  /// A small direct-mapped cache in front of the hash map: neighbouring rays revisit the
  /// same blocks, and a hash lookup at every block change would dominate the traversal.
  VoxelMask& maskOf(const BlockKey& key) {
    CacheEntry& entry = cache_[VoxelIndexHash{}(key) & (kCacheSize - 1)];
    if (entry.slot != kNoSlot && entry.key == key) return masks_[entry.slot];
    const auto [it, inserted] = slot_of_.try_emplace(key, static_cast<std::uint32_t>(keys_.size()));
    if (inserted) {
      keys_.push_back(key);
      masks_.emplace_back();
    }
    entry = {key, it->second};
    return masks_[it->second];
  }

  static constexpr std::size_t kMaxDenseBits = std::size_t{1} << 26;  // 8 MB of grid
  bool dense_ = false;
  bool dirty_ = false;  // the grid may hold marks that finish() has not cleared
  VoxelIndex grid_lo_ = VoxelIndex::Zero();
  int nx_ = 0, ny_ = 0, nz_ = 0;     // multiples of kBlockDim
  std::vector<std::uint64_t> grid_;  // bit (x * ny + y) * nz + z, from grid_lo_
  std::vector<VoxelMask> column_;    // denseToBlocks: the masks of one column of blocks

  static constexpr std::size_t kCacheSize = 1024;
  static constexpr std::uint32_t kNoSlot = ~std::uint32_t{0};
  struct CacheEntry {
    BlockKey key = BlockKey::Zero();
    std::uint32_t slot = kNoSlot;
  };
  std::array<CacheEntry, kCacheSize> cache_{};
  tsl::robin_map<BlockKey, std::uint32_t, VoxelIndexHash> slot_of_;
  std::vector<BlockKey> keys_;
  std::vector<VoxelMask> masks_;  // parallel to keys_

  // markRays' scratch: the rays' walks, sorted by unchecked steps.
  std::vector<RayWalk> walks_;
  std::vector<int> unchecked_;
  std::vector<std::uint32_t> order_, bucket_;
};

}  // namespace socc::map
