#pragma once
// A part of the grid given as a set of blocks (kBlockDim^3 voxels each): what a region rebuild
// erases and integrates again (docs/consistency.md, "Region rebuilds"), so that the rest of the
// grid stays as it is.
#include <tsl/robin_set.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

class BlockRegion {
 public:
  /// Adds blocks (e.g. a scan's footprint: SemanticOccupancyMap::footprint).
  void add(const std::vector<BlockKey>& blocks) {
    for (const BlockKey& key : blocks) insert(key);
  }

  bool contains(const BlockKey& key) const { return blocks_.count(key) != 0; }

  /// Whether one of blocks is in the region.
  bool intersects(const std::vector<BlockKey>& blocks) const {
    return std::any_of(blocks.begin(), blocks.end(), [this](const BlockKey& key) {
      return bounds_.contains(key) && contains(key);  // far from the region: no lookup
    });
  }

  bool empty() const { return blocks_.empty(); }
  std::size_t size() const { return blocks_.size(); }
  const tsl::robin_set<BlockKey, VoxelIndexHash>& blocks() const { return blocks_; }

 private:
  void insert(const BlockKey& key) {
    blocks_.insert(key);
    bounds_.extend(key);
  }

  tsl::robin_set<BlockKey, VoxelIndexHash> blocks_;
  Eigen::AlignedBox3i bounds_;  // of the blocks' keys (empty while there are none)
};

}  // namespace socc::map
