// SemanticOccupancyMap::integrate: scan -> per-voxel frame aggregates -> hits, then
// deduplicated rays -> misses. Hits are applied before misses and mark their voxels, so a
// voxel hit by the scan is never missed by it, and every voxel is missed at most once.
#include <tbb/parallel_pipeline.h>

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

/// Traverses rays [begin, end) into out. Rays from one origin to neighbouring endpoints walk
/// the same voxels until they diverge: each ray skips its common prefix with the previous ray
/// (cheap, exact; remaining repeats are filtered by the scan marks when applying).
void traverseBatch(const Eigen::Vector3d& origin, double voxel_size,
                   const std::vector<Eigen::Vector3d>& ends, std::size_t begin, std::size_t end,
                   std::array<std::vector<VoxelIndex>, 2>& tmp, std::vector<VoxelIndex>& out) {
  out.clear();
  std::vector<VoxelIndex>* ray = &tmp[0];
  std::vector<VoxelIndex>* prev = &tmp[1];
  prev->clear();
  for (std::size_t i = begin; i < end; ++i) {
    ray->clear();
    traverseRay(origin, ends[i], voxel_size, *ray);
    const std::size_t n = std::min(ray->size(), prev->size());
    std::size_t common = 0;
    while (common < n && (*ray)[common] == (*prev)[common]) ++common;
    out.insert(out.end(), ray->begin() + static_cast<std::ptrdiff_t>(common), ray->end());
    std::swap(ray, prev);
  }
}

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

}  // namespace

IntegrationResult SemanticOccupancyMap::integrate(const Eigen::Isometry3d& sensor_pose,
                                                  const LabeledCloud& cloud) {
  if (const std::string err = validate(sensor_pose, cloud); !err.empty())
    throw std::invalid_argument(err);
  Impl& m = *impl_;
  Scratch& s = m.scratch;
  IntegrationResult result;
  result.points_used = summarise(sensor_pose, cloud, m.config, s);

  s.touched.clear();
  Grid::Accessor access(m.grid);
  const SemanticVoxelBehaviour& behaviour = m.behaviour;

  // Hits first.
  for (std::size_t i = 0; i < s.hit_voxels.size(); ++i) {
    const VoxelIndex& v = s.hit_voxels[i];
    Block& block = access.block(blockOf(v));
    const int local = localOf(v);
    markOnce(block, local, s.touched);
    const bool was_observed = block.observed[local];
    const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
    behaviour.onHits(block.log_odds[local], block.acquireStats(local), s.hits[i]);
    block.observed[local] = true;
    m.num_observed += was_observed ? 0 : 1;
    m.num_occupied +=
        (behaviour.isOccupied(block.log_odds[local]) ? 1 : 0) - (was_occupied ? 1 : 0);
  }
  result.voxels_hit = static_cast<std::int32_t>(s.hit_voxels.size());
  result.voxels_touched = result.voxels_hit;

  // Rays: a pipeline traverses batches of rays in parallel while the previous batches are
  // applied serially and in order (the grid is not thread-safe; the result is deterministic).
  if (!s.ray_ends.empty()) {
    const Eigen::Vector3d origin = sensor_pose.translation();
    const double vs = m.config.voxel_size;
    constexpr std::size_t kRaysPerBatch = 64;
    std::size_t next_ray = 0, next_batch = 0;
    const auto applyMisses = [&](const std::vector<VoxelIndex>& voxels) {
      BlockKey key = BlockKey::Zero();
      Block* current = nullptr;
      for (const VoxelIndex& v : voxels) {
        const BlockKey k = blockOf(v);
        if (current == nullptr || k != key) {  // inline fast path: same block as before
          current = &access.block(k);
          key = k;
        }
        Block& block = *current;
        const int local = localOf(v);
        if (!markOnce(block, local, s.touched)) continue;
        const bool was_observed = block.observed[local];
        const bool was_occupied = was_observed && behaviour.isOccupied(block.log_odds[local]);
        if (behaviour.onMiss(block.log_odds[local], block.statsOf(local))) {
          block.releaseStats(local);  // turned free: no ghost of what was here
          ++result.voxels_freed;
        }
        block.observed[local] = true;
        m.num_observed += was_observed ? 0 : 1;
        m.num_occupied -= (was_occupied && !behaviour.isOccupied(block.log_odds[local])) ? 1 : 0;
        ++result.voxels_touched;
      }
    };
    struct Batch {
      std::size_t begin, end;
      std::vector<VoxelIndex>* voxels;
      std::array<std::vector<VoxelIndex>, 2>* tmp;
    };
    m.arena.execute([&] {
      tbb::parallel_pipeline(
          ScanScratch::kRayBatches,
          tbb::make_filter<void, Batch>(
              tbb::filter_mode::serial_in_order,
              [&](tbb::flow_control& fc) -> Batch {
                if (next_ray >= s.ray_ends.size()) {
                  fc.stop();
                  return {};
                }
                // At most kRayBatches tokens live and the last stage runs in order, so the
                // buffer reused here belongs to a batch that has been applied already.
                const std::size_t slot = next_batch++ % ScanScratch::kRayBatches;
                Batch b{next_ray, std::min(s.ray_ends.size(), next_ray + kRaysPerBatch),
                        &s.ray_voxels[slot], &s.ray_tmp[slot]};
                next_ray = b.end;
                return b;
              }) &
              tbb::make_filter<Batch, Batch>(tbb::filter_mode::parallel,
                                             [&](Batch b) {
                                               traverseBatch(origin, vs, s.ray_ends, b.begin, b.end,
                                                             *b.tmp, *b.voxels);
                                               return b;
                                             }) &
              tbb::make_filter<Batch, void>(tbb::filter_mode::serial_in_order,
                                            [&](Batch b) { applyMisses(*b.voxels); }));
    });
  }
  for (Block* block : s.touched) {
    block->scan_mark.reset();
    block->in_scan = false;
  }
  ++m.version;
  return result;
}

}  // namespace socc::map
