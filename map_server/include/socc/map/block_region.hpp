#pragma once
// A part of the grid given as a set of blocks (kBlockDim^3 voxels each): what a region rebuild
// erases and integrates again (docs/consistency.md, "Region rebuilds"), so that the rest of the
// grid stays as it is.
#include <tsl/robin_set.h>

#include <Eigen/Geometry>
#include <cstddef>

#include "socc/map/voxel_grid.hpp"

namespace socc::map {

class BlockRegion {
 public:
  /// Adds every block that a voxel of box (map frame, metres) lies in, with voxels of
  /// voxel_size.
  void addBox(const Eigen::AlignedBox3d& box, double voxel_size) {
    forEachBlock(box, voxel_size, [this](const BlockKey& key) {
      blocks_.insert(key);
      bounds_.extend(key);
      return false;
    });
  }

  bool contains(const BlockKey& key) const { return blocks_.count(key) != 0; }

  /// Whether a block of box (as addBox) is in the region.
  bool intersects(const Eigen::AlignedBox3d& box, double voxel_size) const {
    const VoxelGeometry geometry(voxel_size);
    const Eigen::AlignedBox3i blocks(blockOf(geometry.indexOf(box.min())),
                                     blockOf(geometry.indexOf(box.max())));
    if (!bounds_.intersects(blocks)) return false;  // far from the region: no lookups
    return forEachBlock(box, voxel_size, [this](const BlockKey& key) { return contains(key); });
  }

  bool empty() const { return blocks_.empty(); }
  std::size_t size() const { return blocks_.size(); }
  const tsl::robin_set<BlockKey, VoxelIndexHash>& blocks() const { return blocks_; }

 private:
  /// Calls f(key) for each block of box until f returns true; whether one did.
  template <typename F>
  static bool forEachBlock(const Eigen::AlignedBox3d& box, double voxel_size, F&& f) {
    const VoxelGeometry geometry(voxel_size);
    const BlockKey lo = blockOf(geometry.indexOf(box.min()));
    const BlockKey hi = blockOf(geometry.indexOf(box.max()));
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z)
          if (f(BlockKey(x, y, z))) return true;
    return false;
  }

  tsl::robin_set<BlockKey, VoxelIndexHash> blocks_;
  Eigen::AlignedBox3i bounds_;  // of the blocks' keys (empty while there are none)
};

}  // namespace socc::map
