#pragma once
// Sparse voxel grid container: blocks of 8^3 voxels hashed by block coordinate
// (tsl::robin_map), so access is near constant time and empty space costs nothing.
// The container knows voxel geometry (size, index of a point, centre, block layout) and
// nothing about what a voxel holds: the block type is a template parameter (as Bonxai's
// VoxelGrid<DataT>); the map's is SemanticBlock, and all update rules live in the voxel
// behaviour.
#include <tsl/robin_map.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "socc/recent_lookups.hpp"
#include "socc/voxel.hpp"

namespace socc::map {

// Voxel keys (VoxelIndex, voxelIndex, VoxelIndexHash, indexLess) are socc/voxel.hpp's.

/// Integer block coordinate: voxel index >> kBlockShift per axis.
using BlockKey = Eigen::Vector3i;

inline constexpr int kBlockShift = 3;
inline constexpr int kBlockDim = 1 << kBlockShift;  // 8 voxels per block edge
inline constexpr int kBlockVoxels = kBlockDim * kBlockDim * kBlockDim;

inline BlockKey blockOf(const VoxelIndex& v) {
  // Arithmetic shift floors negative coordinates (guaranteed by GCC/Clang, C++20 standard).
  return {v.x() >> kBlockShift, v.y() >> kBlockShift, v.z() >> kBlockShift};
}
inline int localOf(const VoxelIndex& v) {
  constexpr int m = kBlockDim - 1;
  return ((v.x() & m) << (2 * kBlockShift)) | ((v.y() & m) << kBlockShift) | (v.z() & m);
}
inline VoxelIndex voxelOf(const BlockKey& block, int local) {
  // Multiplication, not <<: shifting negative values left is undefined before C++20.
  constexpr int m = kBlockDim - 1;
  return {block.x() * kBlockDim + ((local >> (2 * kBlockShift)) & m),
          block.y() * kBlockDim + ((local >> kBlockShift) & m),
          block.z() * kBlockDim + (local & m)};
}

/// floor(v) as an int, for v within the int range: std::floor(v) cast to int without the
/// floor (baseline x86-64 has no rounding instruction: a truncation and a compare instead).
inline int floorToInt(double v) {
  const int i = static_cast<int>(v);  // towards zero
  return i - (v < static_cast<double>(i) ? 1 : 0);
}

/// A grid's voxel geometry: size, the voxel holding a point (socc/voxel.hpp's rule), a voxel's
/// centre. A small value: hot loops copy it into a local, which stays in registers.
struct VoxelGeometry {
  explicit VoxelGeometry(double voxel_size) : size(voxel_size), inv_size(1.0 / voxel_size) {}
  /// voxelIndex(p, inv_size): floorToInt of p * inv_size (x and y together in SSE2 lanes).
  VoxelIndex indexOf(const Eigen::Vector3d& p) const {
#ifdef __SSE2__
    const __m128d xy = _mm_mul_pd(_mm_loadu_pd(p.data()), _mm_set1_pd(inv_size));
    const __m128i truncated = _mm_cvttpd_epi32(xy);
    const __m128d below = _mm_cmplt_pd(xy, _mm_cvtepi32_pd(truncated));  // all ones: -1
    const __m128i floored = _mm_add_epi32(
        truncated, _mm_shuffle_epi32(_mm_castpd_si128(below), _MM_SHUFFLE(3, 3, 2, 0)));
    return {_mm_cvtsi128_si32(floored), _mm_cvtsi128_si32(_mm_shuffle_epi32(floored, 1)),
            floorToInt(p.z() * inv_size)};
#else
    const Eigen::Vector3d q = p * inv_size;
    return {floorToInt(q.x()), floorToInt(q.y()), floorToInt(q.z())};
#endif
  }
  Eigen::Vector3d centre(const VoxelIndex& v) const {
    return (v.cast<double>().array() + 0.5).matrix() * size;
  }
  double size;
  double inv_size;
};

/// Block: what one block of kBlockVoxels voxels holds (default-constructible, with
/// memoryBytes()); voxel v of a block is entry localOf(v) of its arrays.
template <typename BlockT>
class VoxelGrid {
 public:
  using Block = BlockT;

  explicit VoxelGrid(double voxel_size) : geometry_(voxel_size) {}

  const VoxelGeometry& geometry() const { return geometry_; }
  double voxelSize() const { return geometry_.size; }
  VoxelIndex indexOf(const Eigen::Vector3d& p) const { return geometry_.indexOf(p); }
  Eigen::Vector3d centre(const VoxelIndex& v) const { return geometry_.centre(v); }
  // unique_ptr keeps block addresses stable across rehashing (cached accessors hold them).
  using BlockMap = tsl::robin_map<BlockKey, std::unique_ptr<Block>, VoxelIndexHash>;

  const Block* find(const BlockKey& key) const {
    const auto it = blocks_.find(key);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  Block* find(const BlockKey& key) {
    const auto it = blocks_.find(key);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  Block& getOrCreate(const BlockKey& key) {
    auto& ptr = blocks_[key];
    if (!ptr) ptr = std::make_unique<Block>();
    return *ptr;
  }

  const BlockMap& blocks() const { return blocks_; }
  std::size_t numBlocks() const { return blocks_.size(); }
  void clear() { blocks_.clear(); }
  /// Drops the block (no-op when absent).
  void erase(const BlockKey& key) { blocks_.erase(key); }

  /// A deep copy (every block copied). Named, not a copy constructor: a grid is large and
  /// copying one should never happen by accident.
  VoxelGrid clone() const {
    VoxelGrid copy(geometry_.size);
    copy.blocks_.reserve(blocks_.size());
    for (const auto& [key, block] : blocks_)
      copy.blocks_.emplace(key, std::make_unique<Block>(*block));
    return copy;
  }

  /// Blocks + statistics pools + hash table (buckets hold key, pointer and probe distance).
  std::size_t memoryBytes() const {
    std::size_t bytes = blocks_.bucket_count() * (sizeof(typename BlockMap::value_type) + 8);
    for (const auto& [key, block] : blocks_) bytes += block->memoryBytes();
    return bytes;
  }

  /// Keys of the existing blocks intersecting the inclusive block range [lo, hi], sorted
  /// lexicographically. Enumerates the range or scans the map, whichever is cheaper.
  std::vector<BlockKey> blocksIn(const BlockKey& lo, const BlockKey& hi) const {
    std::vector<BlockKey> keys;
    if ((hi.array() < lo.array()).any()) return keys;
    const Eigen::Array3d extent = (hi - lo).cast<double>().array() + 1.0;
    if (extent.prod() <= 2.0 * static_cast<double>(blocks_.size()) + 64.0) {
      for (int x = lo.x(); x <= hi.x(); ++x)
        for (int y = lo.y(); y <= hi.y(); ++y)
          for (int z = lo.z(); z <= hi.z(); ++z)
            if (blocks_.count(BlockKey(x, y, z)) != 0) keys.emplace_back(x, y, z);
      return keys;  // already in lexicographic order
    }
    for (const auto& [key, block] : blocks_)
      if ((key.array() >= lo.array()).all() && (key.array() <= hi.array()).all())
        keys.push_back(key);
    std::sort(keys.begin(), keys.end(), indexLess);
    return keys;
  }

  /// Cached accessor for ray traversal: the last block, then a small direct-mapped cache of
  /// recent blocks (rays from one origin keep revisiting the same blocks), then the hash map.
  /// Creates missing blocks.
  class Accessor {
   public:
    explicit Accessor(VoxelGrid& grid) : grid_(grid) {}
    Block& block(const BlockKey& key) {
      if (last_ != nullptr && key == last_key_) return *last_;
      if (Block* const* recent = recent_.find(key)) {
        last_ = *recent;
      } else {
        last_ = &grid_.getOrCreate(key);
        recent_.remember(key, last_);
      }
      last_key_ = key;
      return *last_;
    }

   private:
    VoxelGrid& grid_;
    BlockKey last_key_ = BlockKey::Zero();
    Block* last_ = nullptr;
    RecentLookups<BlockKey, Block*, VoxelIndexHash, 512> recent_;
  };

 private:
  VoxelGeometry geometry_;
  BlockMap blocks_;
};

}  // namespace socc::map
