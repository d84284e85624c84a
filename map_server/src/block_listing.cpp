// SemanticOccupancyMap's block listing for live views (map_delta_t, socc-view): which blocks
// changed since a map version, and their occupied voxels in a compact form.
#include <algorithm>

#include "map_impl.hpp"
#include "occupied_test.hpp"
#include "socc/rounding.hpp"

namespace socc::map {

std::vector<std::array<std::int32_t, 3>> SemanticOccupancyMap::blocksChangedSince(
    std::int64_t since) const {
  std::vector<BlockKey> changed;
  for (const auto& [key, block] : impl_->grid.blocks())
    if (block->occupied_version > since || since < 0) changed.push_back(key);
  std::sort(changed.begin(), changed.end(), indexLess);
  std::vector<std::array<std::int32_t, 3>> keys;
  keys.reserve(changed.size());
  for (const BlockKey& k : changed) keys.push_back({k.x(), k.y(), k.z()});
  return keys;
}

BlockVoxels SemanticOccupancyMap::occupiedInBlocks(
    const std::vector<std::array<std::int32_t, 3>>& keys) const {
  const OccupiedTest occupied(impl_->config.occupancy_threshold);
  BlockVoxels out;
  out.block_key = keys;
  out.block_voxels.reserve(keys.size());
  for (const auto& k : keys) {
    const Block* block = impl_->grid.find(BlockKey(k[0], k[1], k[2]));
    std::int32_t n = 0;
    for (int local = 0; block != nullptr && local < kBlockVoxels; ++local) {
      if (!block->observed[local] || !occupied(block->log_odds[local])) continue;
      const VoxelStats* stats = block->statsOf(local);
      const double p = probability(block->log_odds[local]);
      out.local.push_back(static_cast<std::int16_t>(local));
      out.occupancy.push_back(
          static_cast<std::uint8_t>(roundHalfAway(std::clamp(p, 0.0, 1.0) * 255.0)));
      out.label.push_back(stats != nullptr ? stats->label : std::uint8_t{0});
      ++n;
    }
    out.block_voxels.push_back(n);
  }
  return out;
}

int SemanticOccupancyMap::blockDim() {
  return kBlockDim;
}

}  // namespace socc::map
