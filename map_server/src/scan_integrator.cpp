// SemanticOccupancyMap::integrate: scan -> per-voxel frame aggregates -> hits, then rays ->
// footprint of crossed voxels -> misses. Hits are applied before misses and mark their
// voxels, so a voxel hit by the scan is never missed by it, and every voxel crossed by any
// number of rays is missed exactly once.
//
// Every parallel step works on fixed partitions (by point index, by block hash or by ray
// chunk), never on "whatever each thread got", and grid blocks are created serially in a
// fixed order: the map after a scan is the same bit for bit however many threads ran.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cassert>

#include "map_impl.hpp"
#include "socc/map/ray_traversal.hpp"

namespace socc::map {
namespace {

using PointKind = ScanScratch::PointKind;

std::size_t partitionOf(const VoxelIndex& v) {
  return VoxelIndexHash{}(blockOf(v)) % ScanScratch::kHitPartitions;
}

/// Per point (parallel, each point independent): range gate, map-frame position, voxel.
void classifyPoints(const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                    const MapConfig& config, const Grid& grid, ScanScratch& s) {
  const std::size_t n = cloud.size();
  s.kind.resize(n);
  s.position.resize(n);
  s.voxel.resize(n);
  const Eigen::Matrix3d r = pose.linear();
  const Eigen::Vector3d t = pose.translation();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const VoxelGeometry geometry = grid.geometry();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Eigen::Vector3d ps = cloud.points[i].cast<double>();
                        const double d = ps.norm();
                        PointKind kind = PointKind::kHit;
                        Eigen::Vector3d pm = Eigen::Vector3d::Zero();
                        if (d < config.min_range || (d > config.max_range && !config.raycast)) {
                          kind = PointKind::kSkipped;
                        } else if (d > config.max_range) {
                          kind = PointKind::kClipped;  // clears free space up to max range only
                          pm = r * (ps * (config.max_range / d)) + t;
                        } else {
                          pm = r * ps + t;
                        }
                        s.kind[i] = kind;
                        s.position[i] = pm;
                        s.voxel[i] = geometry.indexOf(pm);
                      }
                    });
}

/// Aggregates, in point order, the hit points whose voxel falls in partition p: the same
/// per-voxel sums as one sequential pass, since a voxel lives in exactly one partition.
void aggregatePartition(std::size_t p, const LabeledCloud& cloud, ScanScratch& s) {
  HitPartition& part = s.partitions[p];
  part.slot_of.clear();
  part.voxels.clear();
  part.frames.clear();
  const bool labeled = cloud.hasLabels();
  VoxelIndex last(0, 0, 0);
  std::uint32_t last_slot = 0;
  bool have_last = false;  // consecutive points often share a voxel: skip the hash then
  for (std::size_t i = 0; i < s.kind.size(); ++i) {
    if (s.kind[i] != PointKind::kHit) continue;
    const VoxelIndex& v = s.voxel[i];
    if (!have_last || v != last) {
      if (partitionOf(v) != p) continue;
      const auto [it, inserted] =
          part.slot_of.try_emplace(v, static_cast<std::uint32_t>(part.voxels.size()));
      if (inserted) {
        part.voxels.push_back(v);
        part.frames.emplace_back();
      }
      last = v;
      last_slot = it->second;
      have_last = true;
    }
    if (labeled)
      part.frames[last_slot].add(s.position[i], cloud.labels[i]);
    else
      part.frames[last_slot].add(s.position[i]);
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
  for (std::size_t i = 0; i < part.voxels.size(); ++i) {
    Block& block = *part.blocks[i];
    const int local = localOf(part.voxels[i]);
    block.scan_mark[local] = true;
    if (!block.in_scan) {
      block.in_scan = true;
      part.touched.push_back(&block);
    }
    const bool was_observed = block.observed[local];
    const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
    behaviour.onHits(block.log_odds[local], block.acquireStats(local), part.frames[i]);
    block.observed[local] = true;
    tally.newly_observed += was_observed ? 0 : 1;
    tally.occupied_delta +=
        (behaviour.isOccupied(block.log_odds[local]) ? 1 : 0) - (was_occupied ? 1 : 0);
    ++tally.touched;
  }
  return tally;
}

/// Applies one miss to every voxel of mask in block that the scan did not hit.
void applyMisses(const SemanticVoxelBehaviour& behaviour, Block& block, const VoxelMask& mask,
                 Tally& tally) {
  for (std::size_t w = 0; w < mask.size(); ++w) {
    for (std::uint64_t bits = mask[w]; bits != 0; bits &= bits - 1) {
      const int local = static_cast<int>(w * 64) + __builtin_ctzll(bits);
      if (block.scan_mark[local]) continue;  // hit by this scan: never also missed
      const bool was_observed = block.observed[local];
      const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
      if (behaviour.onMiss(block.log_odds[local], block.statsOf(local))) {
        block.releaseStats(local);  // turned free: no ghost of what was here
        ++tally.freed;
      }
      block.observed[local] = true;
      tally.newly_observed += was_observed ? 0 : 1;
      tally.occupied_delta -=
          (was_occupied && !behaviour.isOccupied(block.log_odds[local])) ? 1 : 0;
      ++tally.touched;
    }
  }
}

/// Ray ends: each hit voxel's centre (partition order), then each distinct max-range end.
void collectRayEnds(const Grid& grid, ScanScratch& s) {
  const VoxelGeometry geometry = grid.geometry();
  s.ray_ends.clear();
  for (const HitPartition& part : s.partitions)
    for (const VoxelIndex& v : part.voxels) s.ray_ends.push_back(geometry.centre(v));
  s.clipped_of.clear();
  for (std::size_t i = 0; i < s.kind.size(); ++i)
    if (s.kind[i] == PointKind::kClipped && s.clipped_of.try_emplace(s.voxel[i], 0).second)
      s.ray_ends.push_back(s.position[i]);
}

/// Traverses every ray (fixed chunks in parallel) and merges the footprints in chunk order.
const RayFootprint& traverseRays(const Eigen::Vector3d& origin, const Grid& grid, ScanScratch& s) {
  constexpr std::size_t kChunks = ScanScratch::kRayChunks;
  const std::size_t n = s.ray_ends.size();
  tbb::parallel_for(std::size_t{0}, kChunks, [&](std::size_t c) {
    const std::size_t begin = n * c / kChunks, end = n * (c + 1) / kChunks;
    const VoxelGeometry geometry = grid.geometry();
    VoxelIndex lo = geometry.indexOf(origin), hi = lo;
    for (std::size_t i = begin; i < end; ++i) {
      const VoxelIndex v = geometry.indexOf(s.ray_ends[i]);
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    RayFootprint& footprint = s.footprints[c];
    footprint.reset(lo, hi);
    RayFootprint::Marker mark(footprint);
    for (std::size_t i = begin; i < end; ++i)
      forEachVoxelOnRay(origin, s.ray_ends[i], geometry.size, mark);
    footprint.finish();
  });
  RayFootprint& all = s.footprints[0];
  for (std::size_t c = 1; c < kChunks; ++c) all.merge(s.footprints[c]);
  return all;
}

/// Creates the hit voxels' blocks serially (the grid's hash map is not thread-safe) in a fixed
/// order, then applies the partitions' hits in parallel. Hits go first: they mark their
/// voxels, which the misses then skip.
Tally integrateHits(const SemanticVoxelBehaviour& behaviour, Grid::Accessor& access,
                    ScanScratch& s) {
  for (HitPartition& part : s.partitions) {
    part.blocks.resize(part.voxels.size());
    for (std::size_t i = 0; i < part.voxels.size(); ++i)
      part.blocks[i] = &access.block(blockOf(part.voxels[i]));
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
                      const Grid& grid, const Eigen::Vector3d& origin, ScanScratch& s) {
  collectRayEnds(grid, s);
  const RayFootprint& footprint = traverseRays(origin, grid, s);
  s.miss_blocks.resize(footprint.numBlocks());
  for (std::size_t i = 0; i < footprint.numBlocks(); ++i)
    s.miss_blocks[i] = &access.block(footprint.key(i));
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, footprint.numBlocks(), 32), Tally{},
      [&](const tbb::blocked_range<std::size_t>& r, Tally t) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          applyMisses(behaviour, *s.miss_blocks[i], footprint.mask(i), t);
        return t;
      },
      [](Tally x, const Tally& y) { return x += y; });
}

/// Clears the per-scan hit marks of the blocks the hits touched and stamps them, and the blocks
/// the rays crossed, with the map version the scan makes (delta chunks).
void finishBlocks(ScanScratch& s, bool raycast, std::int64_t version) {
  for (HitPartition& part : s.partitions)
    for (Block* block : part.touched) {
      block->scan_mark.reset();
      block->in_scan = false;
      block->version = version;
    }
  if (raycast)
    for (Block* block : s.miss_blocks) block->version = version;
}

}  // namespace

IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud) {
  // The contract, not a check: every caller validates first (the service before journaling
  // the request), and a second walk over the points would cost as much as classifying them.
  assert(validate(sensor_pose, cloud).empty());
  Impl& m = *impl_;
  ScanScratch& s = m.scratch;
  Grid::Accessor access(m.grid);
  IntegrationResult result;
  Tally tally;
  m.arena.execute([&] {
    classifyPoints(sensor_pose, cloud, m.config, m.grid, s);
    tbb::parallel_for(std::size_t{0}, ScanScratch::kHitPartitions,
                      [&](std::size_t p) { aggregatePartition(p, cloud, s); });
    tally = integrateHits(m.behaviour, access, s);
    result.voxels_hit = static_cast<std::int32_t>(tally.touched);
    if (m.config.raycast)
      tally += integrateMisses(m.behaviour, access, m.grid, sensor_pose.translation(), s);
  });
  finishBlocks(s, m.config.raycast, m.version + 1);

  m.num_observed += tally.newly_observed;
  m.num_occupied += tally.occupied_delta;
  result.voxels_touched = static_cast<std::int32_t>(tally.touched);
  result.voxels_freed = static_cast<std::int32_t>(tally.freed);
  result.points_used =
      static_cast<std::int32_t>(std::count(s.kind.begin(), s.kind.end(), PointKind::kHit));
  ++m.version;
  return result;
}

}  // namespace socc::map
