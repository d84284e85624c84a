#pragma once
// The voxels a group of rays passed through, as one 512-bit mask per 8^3 block. Marking is
// idempotent, so rays sharing voxels near the sensor need no deduplication pass, and each
// voxel is later missed exactly once however many rays crossed it.
#include <tsl/robin_map.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

using VoxelMask = std::array<std::uint64_t, kBlockVoxels / 64>;

class RayFootprint {
 public:
  /// Starts an empty footprint for rays whose voxels all lie in the box [lo, hi]. A small
  /// box is covered by a dense array of block masks (no lookups and no data-dependent
  /// branches per step: twice as fast); a large one (fine voxels, long range) by a hash map.
  void reset(const VoxelIndex& lo, const VoxelIndex& hi) {
    slot_of_.clear();
    keys_.clear();
    masks_.clear();
    cache_.fill(CacheEntry{});
    dense_lo_ = blockOf(lo);
    dense_dims_ = (blockOf(hi) - dense_lo_).array() + 1;
    const double blocks = static_cast<double>(dense_dims_.x()) * dense_dims_.y() * dense_dims_.z();
    dense_.clear();
    if (blocks <= static_cast<double>(kMaxDenseBlocks))
      dense_.resize(static_cast<std::size_t>(blocks));  // zeroed
  }

  /// Ends marking: moves the dense blocks that were touched, in index order, to the block
  /// list that numBlocks() / key() / mask() / merge() see.
  void finish() {
    if (dense_.empty()) return;  // hash mode: the list is already complete
    std::size_t i = 0;
    for (int x = 0; x < dense_dims_.x(); ++x)
      for (int y = 0; y < dense_dims_.y(); ++y)
        for (int z = 0; z < dense_dims_.z(); ++z, ++i) {
          const VoxelMask& mask = dense_[i];
          if (std::any_of(mask.begin(), mask.end(), [](std::uint64_t w) { return w != 0; }))
            maskOf(dense_lo_ + BlockKey(x, y, z)) = mask;  // indexed too, for merge()
        }
    dense_.clear();
  }

  /// Marks the voxels of one ray, walked by forEachVoxelOnRay. The current block's mask is
  /// kept in the marker: a ray changes block only every few steps.
  class Marker {
   public:
    explicit Marker(RayFootprint& footprint) : footprint_(footprint) {}
    void operator()(const VoxelIndex& v) {
      const BlockKey key = blockOf(v);
      const int local = localOf(v);
      const std::uint64_t bit = std::uint64_t{1} << (local & 63);
      if (!footprint_.dense_.empty()) {  // the same every step: predicted
        const BlockKey d = key - footprint_.dense_lo_;
        const std::size_t i = (static_cast<std::size_t>(d.x()) * footprint_.dense_dims_.y() +
                               static_cast<std::size_t>(d.y())) *
                                  footprint_.dense_dims_.z() +
                              static_cast<std::size_t>(d.z());
        footprint_.dense_[i][static_cast<std::size_t>(local >> 6)] |= bit;
        return;
      }
      if (mask_ == nullptr || key != key_) enter(key);
      mask_[local >> 6] |= bit;
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

  /// Adds other's voxels; blocks new to this footprint are appended in other's order, so
  /// merging footprints in a fixed order gives a fixed block order.
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

  static constexpr std::size_t kMaxDenseBlocks = std::size_t{1} << 17;  // 8 MB of masks
  BlockKey dense_lo_ = BlockKey::Zero();
  Eigen::Array3i dense_dims_ = Eigen::Array3i::Zero();
  std::vector<VoxelMask> dense_;  // empty: hash mode

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
};

}  // namespace socc::map
