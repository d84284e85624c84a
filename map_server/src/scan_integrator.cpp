// SemanticOccupancyMap::integrate: scan -> per-voxel frame aggregates -> hits, then rays ->
// footprint of crossed voxels -> misses. Hits are applied before misses and mark their
// voxels, so a voxel hit by the scan is never missed by it, and every voxel crossed by any
// number of rays is missed exactly once.
//
// Every parallel step works on fixed partitions (by point range, by block hash or by ray
// chunk), never on "whatever each thread got" (the ray footprint is a set: which thread marks
// a voxel does not matter), and grid blocks are created serially in a fixed order: the map
// after a scan is the same bit for bit however many threads ran.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <vector>

#include "map_impl.hpp"
#include "socc/map/block_region.hpp"
#include "socc/map/ray_traversal.hpp"

namespace socc::map {
namespace {

std::size_t partitionOfBlock(const BlockKey& b) {
  return VoxelIndexHash{}(b) % ScanScratch::kHitPartitions;
}
std::size_t partitionOf(const VoxelIndex& v) {
  return partitionOfBlock(blockOf(v));
}

/// Per point (parallel over fixed ranges of points): range gate, map-frame position, voxel;
/// each range lists its hit points per partition and its clipped points, in point order.
void classifyPoints(const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                    const MapConfig& config, const Grid& grid, ScanScratch& s) {
  const std::size_t n = cloud.size();
  const std::size_t ranges = (n + ScanScratch::kPointRange - 1) / ScanScratch::kPointRange;
  for (HitPartition& part : s.partitions) {
    if (part.hit_capacity < ranges * ScanScratch::kPointRange) {
      part.hit_capacity = ranges * ScanScratch::kPointRange;
      part.hits.reset(new HitPoint[part.hit_capacity]);  // default-initialised: untouched
    }
    part.hit_count.assign(ranges, 0);
  }
  s.clipped.resize(ranges);
  const Eigen::Matrix3d r = pose.linear();
  const Eigen::Vector3d t = pose.translation();
  // |p| within [min_range, max_range] for sure, without the square root (the decisions are
  // those of the norm: the margins are far above the rounding of the squares).
  const double sure_min2 = config.min_range * config.min_range * (1.0 + 1e-9);
  const double sure_max2 = config.max_range * config.max_range * (1.0 - 1e-9);
  tbb::parallel_for(std::size_t{0}, ranges, [&](std::size_t range) {
    const VoxelGeometry geometry = grid.geometry();
    std::array<HitPoint*, ScanScratch::kHitPartitions> out;  // next record per partition
    for (std::size_t p = 0; p < out.size(); ++p)
      out[p] = s.partitions[p].hits.get() + range * ScanScratch::kPointRange;
    std::vector<ScanScratch::ClippedPoint>& clipped = s.clipped[range];
    clipped.clear();
    const std::size_t end = std::min(n, (range + 1) * ScanScratch::kPointRange);
    BlockKey last_block(0, 0, 0);
    std::size_t last_partition = partitionOf(VoxelIndex(0, 0, 0));
    for (std::size_t i = range * ScanScratch::kPointRange; i != end; ++i) {
      const Eigen::Vector3d ps = cloud.points[i].cast<double>();
      const double d2 = ps.squaredNorm();
      if (!(d2 > sure_min2 && d2 < sure_max2)) {  // near or beyond a range limit
        const double d = std::sqrt(d2);           // = ps.norm()
        if (d < config.min_range || (d > config.max_range && !config.raycast)) continue;
        if (d > config.max_range) {  // clears free space up to max range only
          const Eigen::Vector3d pm = r * (ps * (config.max_range / d)) + t;
          clipped.push_back({pm, geometry.indexOf(pm)});
          continue;
        }
      }
      const Eigen::Vector3d pm = r * ps + t;
      const VoxelIndex v = geometry.indexOf(pm);
      const BlockKey block = blockOf(v);
      if (block != last_block) {  // consecutive points mostly share a block: skip the hash
        last_block = block;
        last_partition = partitionOfBlock(block);
      }
      HitPoint& hit = *out[last_partition]++;
      hit.position = pm;
      hit.voxel = v;
      hit.point = static_cast<std::uint32_t>(i);
    }
    for (std::size_t p = 0; p < out.size(); ++p)
      s.partitions[p].hit_count[range] = static_cast<std::uint32_t>(
          out[p] - (s.partitions[p].hits.get() + range * ScanScratch::kPointRange));
  });
}

/// Aggregates partition p's hit points (in point order): the same per-voxel sums as one
/// sequential pass, since a voxel lives in exactly one partition. A run of consecutive points
/// in one voxel is summed in scalars, with PointMoments::add's operations in its order (and
/// sum_sq's symmetric entries once: d(r) d(c) == d(c) d(r)), so the sums are bit for bit
/// those of FrameAggregate::add.
void aggregatePartition(std::size_t p, const LabeledCloud& cloud, ScanScratch& s) {
  HitPartition& part = s.partitions[p];
  part.slot_of.clear();
  part.voxels.clear();
  const bool labeled = cloud.hasLabels();
  for (std::size_t range = 0; range < part.hit_count.size(); ++range) {
    const HitPoint* hit = part.hits.get() + range * ScanScratch::kPointRange;
    const HitPoint* const end = hit + part.hit_count[range];
    while (hit != end) {
      const VoxelIndex voxel = hit->voxel;
      bool inserted = false;
      const std::uint32_t slot = part.slot_of.find(voxel, inserted);
      if (inserted) {
        part.voxels.push_back(voxel);
        if (part.frames.size() < part.voxels.size())
          part.frames.resize(std::max<std::size_t>(256, 2 * part.frames.size()));
      }
      FrameAggregate& frame = part.frames[slot];
      if (inserted) {  // a spare entry: the fields the run does not write
        frame.label_counts.fill(0);
        frame.count = 0;
        frame.labeled = 0;
      }
      std::uint32_t count = frame.count, with_label = frame.labeled;
      double f0 = 0, f1 = 0, f2 = 0, s0 = 0, s1 = 0, s2 = 0;
      double q00 = 0, q01 = 0, q02 = 0, q11 = 0, q12 = 0, q22 = 0;
      if (count != 0) {  // the voxel's earlier run(s)
        f0 = frame.first.x(), f1 = frame.first.y(), f2 = frame.first.z();
        s0 = frame.sum.x(), s1 = frame.sum.y(), s2 = frame.sum.z();
        q00 = frame.sum_sq(0, 0), q01 = frame.sum_sq(0, 1), q02 = frame.sum_sq(0, 2);
        q11 = frame.sum_sq(1, 1), q12 = frame.sum_sq(1, 2), q22 = frame.sum_sq(2, 2);
      }
      do {  // PointMoments::add
        const Eigen::Vector3d& pt = hit->position;
        if (count == 0) {
          f0 = pt.x();
          f1 = pt.y();
          f2 = pt.z();
        }
        ++count;
        const double d0 = pt.x() - f0, d1 = pt.y() - f1, d2 = pt.z() - f2;
        s0 += d0;
        s1 += d1;
        s2 += d2;
        q00 += d0 * d0;
        q01 += d0 * d1;
        q02 += d0 * d2;
        q11 += d1 * d1;
        q12 += d1 * d2;
        q22 += d2 * d2;
        if (labeled) {
          ++frame.label_counts[cloud.labels[hit->point]];
          ++with_label;
        }
        ++hit;
      } while (hit != end && hit->voxel == voxel);
      frame.count = count;
      frame.labeled = with_label;
      frame.first = Eigen::Vector3d(f0, f1, f2);
      frame.sum = Eigen::Vector3d(s0, s1, s2);
      frame.sum_sq << q00, q01, q02, q01, q11, q12, q02, q12, q22;
    }
  }
}

/// Counts of one group of updates (summed over groups: integer sums are exact).
struct Tally {
  std::int64_t newly_observed = 0, occupied_delta = 0, freed = 0, touched = 0;
  Tally& operator+=(const Tally& o) {
    newly_observed += o.newly_observed;
    occupied_delta += o.occupied_delta;
    freed += o.freed;
    touched += o.touched;
    return *this;
  }
};

/// Applies partition p's hits to its (already created) blocks and marks the voxels.
Tally applyHits(const SemanticVoxelBehaviour& behaviour, HitPartition& part) {
  Tally tally;
  part.touched.clear();
  const std::size_t n = part.voxels.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (part.blocks[i] == nullptr) continue;  // outside the region integrated
    Block& block = *part.blocks[i];
    const int local = localOf(part.voxels[i]);
    block.scan_mark[static_cast<std::size_t>(local >> 6)] |= std::uint64_t{1} << (local & 63);
    if (!block.in_scan) {
      block.in_scan = true;
      part.touched.push_back(&block);
    }
    const bool was_observed = block.observed[local];
    const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
    VoxelStats& stats = block.acquireStats(local);
    behaviour.onHits(block.log_odds[local], stats, part.frames[i]);
    block.setMissClass(local, behaviour.missClass(stats));
    block.observed[local] = true;
    tally.newly_observed += was_observed ? 0 : 1;
    tally.occupied_delta +=
        (behaviour.isOccupied(block.log_odds[local]) ? 1 : 0) - (was_occupied ? 1 : 0);
    ++tally.touched;
  }
  return tally;
}

/// Applies one miss to every voxel of mask in block that the scan did not hit: onMiss, with
/// the miss class the block keeps for voxels with statistics (computed from them once when
/// not known, e.g. after loading a snapshot). A miss on a voxel that may be occupied stamps
/// the block's occupied_version.
void applyMisses(const SemanticVoxelBehaviour& behaviour, Block& block, const VoxelMask& mask,
                 std::int64_t version, Tally& tally) {
  const float plain_miss = behaviour.missLogOdds(nullptr);
  bool seen_change = false;
  for (std::size_t w = 0; w < mask.size(); ++w) {
    // Voxels hit by this scan are never also missed.
    for (std::uint64_t bits = mask[w] & ~block.scan_mark[w]; bits != 0; bits &= bits - 1) {
      const int local = static_cast<int>(w * 64) + __builtin_ctzll(bits);
      float& log_odds = block.log_odds[static_cast<std::size_t>(local)];
      const bool was_observed = block.observed[local];
      const bool was_occupied = was_observed && behaviour.isOccupied(log_odds);
      seen_change = seen_change || behaviour.nearOccupied(log_odds);
      const bool has_stats = block.slot[static_cast<std::size_t>(local)] != kNoStats;
      float miss = plain_miss;
      if (has_stats) {
        int miss_class = block.missClass(local);
        if (miss_class == 0) {
          miss_class = behaviour.missClass(*block.statsOf(local));
          block.setMissClass(local, miss_class);
        }
        miss = behaviour.classMissLogOdds(miss_class);
      }
      log_odds = std::clamp(log_odds + miss, behaviour.clampMin(), behaviour.clampMax());
      const bool occupied = behaviour.isOccupied(log_odds);
      if (has_stats && !occupied) {
        block.releaseStats(local);  // turned free: no ghost of what was here
        ++tally.freed;
      }
      block.observed[local] = true;
      tally.newly_observed += was_observed ? 0 : 1;
      tally.occupied_delta -= (was_occupied && !occupied) ? 1 : 0;
      ++tally.touched;
    }
  }
  if (seen_change) block.occupied_version = version;
}

/// integrate's first steps: the scan's hit voxels with their frame aggregates, per partition.
void aggregateHits(const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                   const MapConfig& config, const Grid& grid, ScanScratch& s) {
  classifyPoints(pose, cloud, config, grid, s);
  tbb::parallel_for(std::size_t{0}, ScanScratch::kHitPartitions,
                    [&](std::size_t p) { aggregatePartition(p, cloud, s); });
}

/// One footprint per thread of the arena (traverseRays).
void sizeFootprints(const tbb::task_arena& arena, ScanScratch& s) {
  const auto threads = static_cast<std::size_t>(arena.max_concurrency());
  if (s.footprints.size() < threads) s.footprints.resize(threads);
}

/// Ray ends: each hit voxel's centre (partition order), then each distinct max-range end.
void collectRayEnds(const Grid& grid, ScanScratch& s) {
  const VoxelGeometry geometry = grid.geometry();
  s.ray_ends.clear();
  for (const HitPartition& part : s.partitions)
    for (const VoxelIndex& v : part.voxels) s.ray_ends.push_back(geometry.centre(v));
  s.clipped_of.clear();
  for (const std::vector<ScanScratch::ClippedPoint>& range : s.clipped)
    for (const ScanScratch::ClippedPoint& c : range)
      if (s.clipped_of.try_emplace(c.voxel, 0).second) s.ray_ends.push_back(c.position);
}

/// Traverses every ray (fixed chunks in parallel, each thread into its own footprint) and
/// merges the footprints into footprints[0], which lists its blocks in key order.
const RayFootprint& traverseRays(const Eigen::Vector3d& origin, const Grid& grid, ScanScratch& s) {
  constexpr std::size_t kChunks = ScanScratch::kRayChunks;
  const std::size_t n = s.ray_ends.size();
  const VoxelGeometry geometry = grid.geometry();
  std::array<VoxelIndex, kChunks> lo, hi;
  tbb::parallel_for(std::size_t{0}, kChunks, [&](std::size_t c) {
    const std::size_t begin = n * c / kChunks, end = n * (c + 1) / kChunks;
    lo[c] = hi[c] = geometry.indexOf(origin);
    for (std::size_t i = begin; i < end; ++i) {
      const VoxelIndex v = geometry.indexOf(s.ray_ends[i]);
      lo[c] = lo[c].cwiseMin(v);
      hi[c] = hi[c].cwiseMax(v);
    }
  });
  for (std::size_t c = 1; c < kChunks; ++c) {
    lo[0] = lo[0].cwiseMin(lo[c]);
    hi[0] = hi[0].cwiseMax(hi[c]);
  }
  for (RayFootprint& footprint : s.footprints) footprint.reset(lo[0], hi[0]);
  std::vector<char> used(s.footprints.size(), 0);  // by arena slot; each set by its thread
  tbb::parallel_for(std::size_t{0}, kChunks, [&](std::size_t c) {
    const std::size_t begin = n * c / kChunks, end = n * (c + 1) / kChunks;
    const auto slot = static_cast<std::size_t>(tbb::this_task_arena::current_thread_index());
    s.footprints[slot].markRays(origin, s.ray_ends.data() + begin, end - begin, geometry.size);
    used[slot] = 1;
  });
  RayFootprint& all = s.footprints[0];
  for (std::size_t slot = 1; slot < s.footprints.size(); ++slot)
    if (used[slot]) all.absorb(s.footprints[slot]);
  all.finish();
  return all;
}

/// Creates the hit voxels' blocks serially (the grid's hash map is not thread-safe) in a fixed
/// order, then applies the partitions' hits in parallel. Hits go first: they mark their
/// voxels, which the misses then skip. With a region, voxels outside it get no block (null).
Tally integrateHits(const SemanticVoxelBehaviour& behaviour, Grid::Accessor& access,
                    const BlockRegion* within, ScanScratch& s) {
  for (HitPartition& part : s.partitions) {
    part.blocks.resize(part.voxels.size());
    for (std::size_t i = 0; i < part.voxels.size(); ++i) {
      const BlockKey key = blockOf(part.voxels[i]);
      part.blocks[i] = within && !within->contains(key) ? nullptr : &access.block(key);
    }
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, ScanScratch::kHitPartitions, 1), Tally{},
      [&](const tbb::blocked_range<std::size_t>& r, Tally t) {
        for (std::size_t p = r.begin(); p != r.end(); ++p)
          t += applyHits(behaviour, s.partitions[p]);
        return t;
      },
      [](Tally x, const Tally& y) { return x += y; });
}

/// One miss for every voxel that a ray from origin to a ray end crosses and the scan did not
/// hit. Blocks are created serially, misses applied in parallel by block: a voxel lives in one
/// block and a miss's effect does not depend on the order of other voxels' misses.
Tally integrateMisses(const SemanticVoxelBehaviour& behaviour, Grid::Accessor& access,
                      const Grid& grid, const Eigen::Vector3d& origin, std::int64_t version,
                      const BlockRegion* within, ScanScratch& s) {
  collectRayEnds(grid, s);
  const RayFootprint& footprint = traverseRays(origin, grid, s);
  s.miss_blocks.resize(footprint.numBlocks());
  for (std::size_t i = 0; i < footprint.numBlocks(); ++i) {
    const BlockKey key = footprint.key(i);
    s.miss_blocks[i] = within && !within->contains(key) ? nullptr : &access.block(key);
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, footprint.numBlocks(), 32), Tally{},
      [&](const tbb::blocked_range<std::size_t>& r, Tally t) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (s.miss_blocks[i] != nullptr)
            applyMisses(behaviour, *s.miss_blocks[i], footprint.mask(i), version, t);
        return t;
      },
      [](Tally x, const Tally& y) { return x += y; });
}

/// Clears the per-scan hit marks of the blocks the hits touched and stamps them, and the blocks
/// the rays crossed, with the map version the scan makes (delta chunks).
void finishBlocks(ScanScratch& s, bool raycast, std::int64_t version) {
  for (HitPartition& part : s.partitions)
    for (Block* block : part.touched) {
      block->scan_mark.fill(0);
      block->in_scan = false;
      block->version = version;
      block->occupied_version = version;
    }
  if (raycast)
    for (Block* block : s.miss_blocks)
      if (block != nullptr) block->version = version;
}

/// The blocks of the scan's hit voxels and, with rays, of the voxels they crossed (the
/// footprint traverseRays left in footprints[0]), in key order.
std::vector<BlockKey> listFootprint(const ScanScratch& s, bool raycast) {
  std::vector<BlockKey> hit;
  for (const HitPartition& part : s.partitions)
    for (const VoxelIndex& v : part.voxels)
      if (hit.empty() || blockOf(v) != hit.back()) hit.push_back(blockOf(v));
  std::sort(hit.begin(), hit.end(), indexLess);
  hit.erase(std::unique(hit.begin(), hit.end()), hit.end());
  if (!raycast) return hit;
  const RayFootprint& rays = s.footprints[0];
  std::vector<BlockKey> crossed(rays.numBlocks());
  for (std::size_t i = 0; i < crossed.size(); ++i) crossed[i] = rays.key(i);
  std::vector<BlockKey> all;
  all.reserve(crossed.size() + hit.size());
  std::set_union(hit.begin(), hit.end(), crossed.begin(), crossed.end(), std::back_inserter(all),
                 indexLess);
  return all;
}

}  // namespace

// The contract, not a check: every caller validates first (the service before journaling the
// request), and a second walk over the points would cost as much as classifying them.
IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud) {
  assert(validate(sensor_pose, cloud).empty());
  return impl_->integrate(sensor_pose, cloud, nullptr, nullptr);
}

IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud,
                                                  const BlockRegion& within) {
  assert(validate(sensor_pose, cloud).empty());
  return impl_->integrate(sensor_pose, cloud, &within, nullptr);
}

IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud,
                                                  std::vector<BlockKey>& footprint) {
  assert(validate(sensor_pose, cloud).empty());
  return impl_->integrate(sensor_pose, cloud, nullptr, &footprint);
}

std::vector<BlockKey> SemanticOccupancyMap::footprint(const Eigen::Isometry3d& sensor_pose,
                                                      const LabeledCloud& cloud) {
  assert(validate(sensor_pose, cloud).empty());
  return impl_->footprint(sensor_pose, cloud);
}

// integrate's steps up to the rays' footprint, applying nothing.
std::vector<BlockKey> SemanticOccupancyMap::Impl::footprint(const Eigen::Isometry3d& sensor_pose,
                                                            const LabeledCloud& cloud) {
  ScanScratch& s = scratch;
  sizeFootprints(arena, s);
  arena.execute([&] {
    aggregateHits(sensor_pose, cloud, config, grid, s);
    if (config.raycast) {
      collectRayEnds(grid, s);
      traverseRays(sensor_pose.translation(), grid, s);
    }
  });
  return listFootprint(s, config.raycast);
}

IntegrationResult SemanticOccupancyMap::Impl::integrate(const Eigen::Isometry3d& sensor_pose,
                                                        const LabeledCloud& cloud,
                                                        const BlockRegion* within,
                                                        std::vector<BlockKey>* footprint) {
  Impl& m = *this;
  ScanScratch& s = m.scratch;
  Grid::Accessor access(m.grid);
  IntegrationResult result;
  Tally tally;
  sizeFootprints(m.arena, s);
  m.arena.execute([&] {
    aggregateHits(sensor_pose, cloud, m.config, m.grid, s);
    tally = integrateHits(m.behaviour, access, within, s);
    result.voxels_hit = static_cast<std::int32_t>(tally.touched);
    if (m.config.raycast)
      tally += integrateMisses(m.behaviour, access, m.grid, sensor_pose.translation(),
                               m.version + 1, within, s);
  });
  finishBlocks(s, m.config.raycast, m.version + 1);
  if (footprint != nullptr) *footprint = listFootprint(s, m.config.raycast);

  m.num_observed += tally.newly_observed;
  m.num_occupied += tally.occupied_delta;
  result.voxels_touched = static_cast<std::int32_t>(tally.touched);
  result.voxels_freed = static_cast<std::int32_t>(tally.freed);
  std::size_t hits = 0;
  for (const HitPartition& part : s.partitions)
    for (const std::uint32_t count : part.hit_count) hits += count;
  result.points_used = static_cast<std::int32_t>(hits);
  ++m.version;
  return result;
}

}  // namespace socc::map
