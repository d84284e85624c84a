// SemanticOccupancyMap::integrate: scan -> per-voxel frame aggregates -> hits, then
// deduplicated rays -> misses. Hits are applied before misses and mark their voxels, so a
// voxel hit by the scan is never missed by it, and every voxel is missed at most once.
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <stdexcept>

#include "map_impl.hpp"
#include "socc/map/ray_traversal.hpp"

namespace socc::map {
namespace {

using Scratch = ScanScratch;

/// Reduces the scan to one aggregate per hit voxel and one ray end per distinct endpoint
/// voxel (hit voxel centres, then clipped max-range ends). Returns the points used.
std::int32_t summarise(const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                       const MapConfig& config, Scratch& s) {
  s.hit_of.clear();
  s.clipped_of.clear();
  s.hit_voxels.clear();
  s.hits.clear();
  s.ray_ends.clear();
  const double inv = 1.0 / config.voxel_size;
  const Eigen::Matrix3d r = pose.linear();
  const Eigen::Vector3d t = pose.translation();
  std::vector<Eigen::Vector3d> clipped_ends;

  std::int32_t used = 0;
  VoxelIndex last(0, 0, 0);
  std::uint32_t last_slot = 0;
  bool have_last = false;  // consecutive points often share a voxel: skip the hash then
  const bool labeled = cloud.hasLabels();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d ps = cloud.points[i].cast<double>();
    const double range = ps.norm();
    if (range < config.min_range) continue;
    if (range > config.max_range) {
      if (!config.raycast) continue;
      const Eigen::Vector3d end = r * (ps * (config.max_range / range)) + t;
      if (s.clipped_of.try_emplace(voxelIndex(end, inv), 0).second) clipped_ends.push_back(end);
      continue;
    }
    ++used;
    const Eigen::Vector3d pm = r * ps + t;
    const VoxelIndex v = voxelIndex(pm, inv);
    if (!have_last || v != last) {
      const auto [it, inserted] =
          s.hit_of.try_emplace(v, static_cast<std::uint32_t>(s.hit_voxels.size()));
      if (inserted) {
        s.hit_voxels.push_back(v);
        s.hits.emplace_back();
      }
      last = v;
      last_slot = it->second;
      have_last = true;
    }
    if (labeled)
      s.hits[last_slot].add(pm, cloud.labels[i]);
    else
      s.hits[last_slot].add(pm);
  }
  if (config.raycast) {
    for (const VoxelIndex& v : s.hit_voxels)
      s.ray_ends.push_back((v.cast<double>().array() + 0.5).matrix() * config.voxel_size);
    s.ray_ends.insert(s.ray_ends.end(), clipped_ends.begin(), clipped_ends.end());
  }
  return used;
}

/// Block owner (0 or 1): the parity of x + y + z, so neighbouring blocks alternate and the
/// two owners get similar shares of every ray.
int ownerOf(const BlockKey& k) {
  return (k.x() ^ k.y() ^ k.z()) & 1;
}

/// Traverses rays [begin, end) into out. Rays from one origin to neighbouring endpoints walk
/// the same voxels until they diverge: each ray skips its common prefix with the previous ray
/// (cheap, exact; remaining repeats are filtered by the scan marks when applying). Only reads
/// the grid: blocks that do not exist yet are listed in `missing` and created before the
/// misses are applied.
void traverseRays(const Eigen::Vector3d& origin, double voxel_size, const Grid& grid,
                  const std::vector<Eigen::Vector3d>& ends, std::size_t begin, std::size_t end,
                  std::array<std::vector<VoxelIndex>, 2>& tmp, std::vector<VoxelIndex>& out,
                  std::vector<BlockKey>& missing) {
  out.clear();
  missing.clear();
  std::vector<VoxelIndex>* ray = &tmp[0];
  std::vector<VoxelIndex>* prev = &tmp[1];
  prev->clear();
  BlockKey key = BlockKey::Zero();
  bool have_key = false;
  for (std::size_t i = begin; i < end; ++i) {
    ray->clear();
    traverseRay(origin, ends[i], voxel_size, *ray);
    const std::size_t n = std::min(ray->size(), prev->size());
    std::size_t common = 0;
    while (common < n && (*ray)[common] == (*prev)[common]) ++common;
    for (std::size_t j = common; j < ray->size(); ++j) {
      const BlockKey k = blockOf((*ray)[j]);
      if (have_key && k == key) continue;  // rays stay in a block for several voxels
      key = k;
      have_key = true;
      if (grid.find(k) == nullptr && (missing.empty() || missing.back() != k)) missing.push_back(k);
    }
    out.insert(out.end(), ray->begin() + static_cast<std::ptrdiff_t>(common), ray->end());
    std::swap(ray, prev);
  }
}

/// Read-only block lookup for one owner: the last block, then a small direct-mapped cache
/// (rays from one origin keep revisiting the same blocks), then the hash map. Safe to use
/// from several threads while nobody inserts blocks.
class BlockLookup {
 public:
  explicit BlockLookup(Grid& grid) : grid_(grid) {}
  Block& block(const BlockKey& key) {
    if (last_ != nullptr && key == last_key_) return *last_;
    Entry& e = cache_[IndexHash{}(key) & (kCacheSize - 1)];
    if (e.block == nullptr || e.key != key) {
      e.block = grid_.find(key);  // exists: created before the parallel phase
      e.key = key;
    }
    last_ = e.block;
    last_key_ = key;
    return *last_;
  }

 private:
  static constexpr std::size_t kCacheSize = 256;
  struct Entry {
    BlockKey key = BlockKey::Zero();
    Block* block = nullptr;
  };
  Grid& grid_;
  BlockKey last_key_ = BlockKey::Zero();
  Block* last_ = nullptr;
  std::array<Entry, kCacheSize> cache_{};
};

/// Marks a voxel as updated by this scan; false when it already was.
bool markOnce(Block& block, int local, std::vector<Block*>& touched) {
  if (block.scan_mark[local]) return false;
  block.scan_mark[local] = true;
  if (!block.in_scan) {
    block.in_scan = true;
    touched.push_back(&block);
  }
  return true;
}

/// What one owner changed; summed after the parallel phase.
struct OwnerTally {
  std::int64_t observed = 0;  // newly observed voxels
  std::int64_t occupied = 0;  // change of the occupied count
  std::int32_t touched = 0;   // voxels missed
  std::int32_t freed = 0;
};

/// Applies everything of one owner: its hits (in scan order), then the misses of part 0 and
/// part 1 (ray order). Every block has exactly one owner, so owners never share a block, and
/// each block sees its updates in the same order whatever the number of threads.
OwnerTally applyOwner(int owner, const SemanticVoxelBehaviour& behaviour, Grid& grid,
                      ScanScratch& s) {
  std::vector<Block*>& touched = s.touched[owner];
  touched.clear();
  OwnerTally t;
  for (std::size_t i = 0; i < s.hit_voxels.size(); ++i) {
    const VoxelIndex& v = s.hit_voxels[i];
    if (ownerOf(blockOf(v)) != owner) continue;
    Block& block = *s.hit_blocks[i];
    const int local = localOf(v);
    markOnce(block, local, touched);
    const bool was_observed = block.observed[local];
    const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
    behaviour.onHits(block.log_odds[local], block.acquireStats(local), s.hits[i]);
    block.observed[local] = true;
    t.observed += was_observed ? 0 : 1;
    t.occupied += (behaviour.isOccupied(block.log_odds[local]) ? 1 : 0) - (was_occupied ? 1 : 0);
  }
  BlockLookup lookup(grid);
  for (int part = 0; part < ScanScratch::kParts; ++part) {
    BlockKey key = BlockKey::Zero();
    Block* current = nullptr;
    bool have_key = false, mine = false;
    for (const VoxelIndex& v : s.misses[part]) {
      const BlockKey k = blockOf(v);
      if (!have_key || k != key) {  // inline fast path: same block as before
        key = k;
        have_key = true;
        mine = ownerOf(k) == owner;
        current = mine ? &lookup.block(k) : nullptr;
      }
      if (!mine) continue;
      Block& block = *current;
      const int local = localOf(v);
      if (!markOnce(block, local, touched)) continue;
      const bool was_observed = block.observed[local];
      const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
      if (behaviour.onMiss(block.log_odds[local], block.statsOf(local))) {
        block.releaseStats(local);  // turned free: no ghost of what was here
        ++t.freed;
      }
      block.observed[local] = true;
      t.observed += was_observed ? 0 : 1;
      t.occupied -= (was_occupied && !behaviour.isOccupied(block.log_odds[local])) ? 1 : 0;
      ++t.touched;
    }
  }
  return t;
}

}  // namespace

IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud) {
  if (const std::string err = validate(sensor_pose, cloud); !err.empty())
    throw std::invalid_argument(err);
  Impl& m = *impl_;
  Scratch& s = m.scratch;
  IntegrationResult result;
  result.points_used = summarise(sensor_pose, cloud, m.config, s);
  result.voxels_hit = static_cast<std::int32_t>(s.hit_voxels.size());
  result.voxels_touched = result.voxels_hit;

  // The grid may only grow serially: create the hit blocks now (consecutive points mostly
  // share a block, so the cached accessor rarely hashes).
  s.hit_blocks.clear();
  {
    Grid::Accessor access(m.grid);
    for (const VoxelIndex& v : s.hit_voxels) s.hit_blocks.push_back(&access.block(blockOf(v)));
  }

  // Phase 1 (parallel, read-only grid): each part traverses a contiguous half of the rays.
  constexpr int kParts = ScanScratch::kParts;
  const Eigen::Vector3d origin = sensor_pose.translation();
  const double vs = m.config.voxel_size;
  const std::size_t num_rays = s.ray_ends.size();
  const auto traversePart = [&](int part) {
    const std::size_t begin = num_rays * static_cast<std::size_t>(part) / kParts;
    const std::size_t end = num_rays * static_cast<std::size_t>(part + 1) / kParts;
    traverseRays(origin, vs, m.grid, s.ray_ends, begin, end, s.ray_tmp[part], s.misses[part],
                 s.missing_blocks[part]);
  };
  m.arena.execute(
      [&] { tbb::parallel_invoke([&] { traversePart(0); }, [&] { traversePart(1); }); });
  for (const auto& keys : s.missing_blocks)
    for (const BlockKey& k : keys) m.grid.getOrCreate(k);

  // Phase 2 (parallel): each owner applies the hits, then the misses, of its own blocks.
  // Hits come first and mark their voxels, so a hit voxel is never missed by the same scan.
  std::array<OwnerTally, kParts> tally;
  m.arena.execute([&] {
    tbb::parallel_invoke([&] { tally[0] = applyOwner(0, m.behaviour, m.grid, s); },
                         [&] { tally[1] = applyOwner(1, m.behaviour, m.grid, s); });
  });
  for (int owner = 0; owner < kParts; ++owner) {
    m.num_observed += tally[owner].observed;
    m.num_occupied += tally[owner].occupied;
    result.voxels_touched += tally[owner].touched;
    result.voxels_freed += tally[owner].freed;
    for (Block* block : s.touched[owner]) {
      block->scan_mark.reset();
      block->in_scan = false;
    }
  }
  ++m.version;
  return result;
}

}  // namespace socc::map
