#include "view_stream.hpp"

#include <utility>

namespace socc::service {
namespace {

map_delta_t deltaHeader(const map::SemanticOccupancyMap& map, std::int8_t kind,
                        std::int64_t utime) {
  map_delta_t m{};
  m.utime = utime;
  m.epoch = map.epoch();
  m.map_version = map.version();
  m.kind = kind;
  m.voxel_size = map.config().voxel_size;
  m.block_dim = map::SemanticOccupancyMap::blockDim();
  m.num_map_blocks = map.stats().num_blocks;
  m.block_key.resize(3);
  return m;
}

// Appends the voxels of blocks to a message (the blocks' contents are whole: never split).
void appendBlocks(map_delta_t& m, const map::BlockVoxels& blocks) {
  for (std::size_t b = 0; b < blocks.block_key.size(); ++b) {
    for (int a = 0; a < 3; ++a) m.block_key[a].push_back(blocks.block_key[b][a]);
    m.block_voxels.push_back(static_cast<std::int16_t>(blocks.block_voxels[b]));
  }
  m.local.insert(m.local.end(), blocks.local.begin(), blocks.local.end());
  m.occupancy.insert(m.occupancy.end(), blocks.occupancy.begin(), blocks.occupancy.end());
  m.label.insert(m.label.end(), blocks.label.begin(), blocks.label.end());
  m.num_blocks = static_cast<std::int32_t>(m.block_voxels.size());
  m.num_voxels = static_cast<std::int32_t>(m.local.size());
}

// FNV-1a over what a view shows of a block (voxels, classes, occupancy in kOccupancyStep steps).
std::uint64_t fingerprint(const map::BlockVoxels& block) {
  std::uint64_t h = 14695981039346656037ull;
  const auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (std::size_t v = 0; v < block.local.size(); ++v) {
    mix(static_cast<std::uint64_t>(block.local[v]));
    mix(block.label[v]);
    mix(block.occupancy[v] / kOccupancyStep);
  }
  return h;
}

}  // namespace

void ViewStream::emit(const map::SemanticOccupancyMap& map, std::deque<Key>& keys,
                      std::size_t budget, std::int8_t kind, std::int64_t utime,
                      std::vector<map_delta_t>& out) {
  std::size_t sent = 0;
  map_delta_t message = deltaHeader(map, kind, utime);
  // A block at a time: its voxel count is known only once read (at most 512).
  while (!keys.empty() && sent < budget) {
    const Key key = keys.front();
    keys.pop_front();
    Sent& last = sent_[key];
    if (kind == map_delta_t::REFRESH && last.cycle == cycle_) continue;  // sent this cycle
    const map::BlockVoxels block = map.occupiedInBlocks({key});
    const std::uint64_t print = fingerprint(block);
    if (kind == map_delta_t::CHANGED) {
      pending_set_.erase(key);
      // Nothing a view would see (a block never sent counts as empty).
      if (print == (last.cycle >= 0 ? last.fingerprint : fingerprint({}))) continue;
    }
    last = {print, cycle_};
    sent += block.local.size();
    appendBlocks(message, block);
    if (message.local.size() >= budget_.message_voxels) {
      out.push_back(std::move(message));
      message = deltaHeader(map, kind, utime);
    }
  }
  if (message.num_blocks > 0) out.push_back(std::move(message));
}

std::vector<map_delta_t> ViewStream::next(const map::SemanticOccupancyMap& map,
                                          std::int64_t utime) {
  if (map.epoch() != epoch_) {  // a new map: everything is new, nothing pending is valid
    epoch_ = map.epoch();
    seen_version_ = -1;
    pending_.clear();
    pending_set_.clear();
    refresh_.clear();
    sent_.clear();
  }
  if (map.version() != seen_version_) {
    for (const Key& key : map.blocksChangedSince(seen_version_))
      if (pending_set_.insert(key).second) pending_.push_back(key);
    seen_version_ = map.version();
  }
  if (refresh_.empty()) {  // the next cycle: every block of the map as it is now
    const std::vector<Key> all = map.blocksChangedSince(-1);
    refresh_.assign(all.begin(), all.end());
    ++cycle_;
  }
  std::vector<map_delta_t> out;
  emit(map, pending_, budget_.changed_voxels, map_delta_t::CHANGED, utime, out);
  emit(map, refresh_, budget_.refresh_voxels, map_delta_t::REFRESH, utime, out);
  return out;
}

}  // namespace socc::service
