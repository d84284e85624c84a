#include "socc/odom/chunk_cache.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "socc/rpc/map_client.hpp"

namespace socc::odom {

chunk_request_t featureChunkRequest(const Eigen::Vector3d& center, double radius,
                                    double occupancy_threshold, bool with_moments) {
  chunk_request_t r = rpc::sphereChunkRequest(center, radius);
  r.occupancy_threshold = static_cast<float>(occupancy_threshold);
  if (with_moments) r.fields |= chunk_request_t::FIELD_MOMENTS;
  return r;
}

chunk_request_t ChunkCache::request(const Eigen::Vector3d& center, double radius) const {
  chunk_request_t r = featureChunkRequest(center, radius, occupancy_threshold_, true);
  if (held_) {
    r.since_epoch = held_->epoch;
    r.since_version = held_->version;
    for (int a = 0; a < 3; ++a) r.since_center[a] = held_->center[a];
    r.since_radius = held_->radius;
  }
  return r;
}

void ChunkCache::reset() {
  held_.reset();
  blocks_.clear();
}

LocalMap ChunkCache::apply(const chunk_reply_t& reply, const Eigen::Vector3d& center,
                           double radius) {
  std::vector<MapVoxel> voxels;
  try {
    voxels = decodeChunkVoxels(reply);  // checks the block lists too
    if (reply.delta_of_version >= 0 &&
        (!held_ || reply.map_epoch != held_->epoch || reply.delta_of_version != held_->version))
      throw std::invalid_argument("malformed chunk reply: a delta on version " +
                                  std::to_string(reply.delta_of_version) +
                                  ", which this client does not hold");
  } catch (const std::invalid_argument&) {
    reset();
    throw;
  }
  if (reply.delta_of_version < 0) blocks_.clear();  // complete: nothing held stays
  replaceBlocks(reply, std::move(voxels));
  dropBlocksOutside(center, radius, reply.voxel_size * reply.block_dim);
  LocalMap map = build(center, radius, reply);
  if (reply.truncated)
    reset();  // an incomplete answer cannot be the base of a delta
  else
    held_ = Held{reply.map_epoch, reply.map_version, center, radius};
  return map;
}

void ChunkCache::replaceBlocks(const chunk_reply_t& reply, std::vector<MapVoxel> voxels) {
  std::size_t next = 0;
  for (std::size_t b = 0; b < reply.block_voxels.size(); ++b) {
    const VoxelIndex key(reply.block[0][b], reply.block[1][b], reply.block[2][b]);
    const auto n = static_cast<std::size_t>(reply.block_voxels[b]);
    std::vector<MapVoxel> kept;
    for (std::size_t i = next; i < next + n; ++i)
      if (occupiedAt(voxels[i], occupancy_threshold_)) kept.push_back(voxels[i]);
    next += n;
    if (kept.empty())
      blocks_.erase(key);
    else
      blocks_[key] = std::move(kept);
  }
}

void ChunkCache::dropBlocksOutside(const Eigen::Vector3d& center, double radius,
                                   double block_size) {
  for (auto it = blocks_.begin(); it != blocks_.end();) {
    const Eigen::Vector3d lo = it->first.cast<double>() * block_size;
    const Eigen::Vector3d hi = (lo.array() + block_size).matrix();
    const Eigen::Vector3d nearest = center.cwiseMax(lo).cwiseMin(hi);
    if ((nearest - center).squaredNorm() > radius * radius)
      it = blocks_.erase(it);
    else
      ++it;
  }
}

LocalMap ChunkCache::build(const Eigen::Vector3d& center, double radius,
                           const chunk_reply_t& reply) const {
  // Blocks in key order and voxels as sent, each voxel by its centre as the server tests it:
  // the order and content of a complete chunk of this sphere.
  std::vector<VoxelIndex> keys;
  keys.reserve(blocks_.size());
  std::size_t count = 0;
  for (const auto& [key, voxels] : blocks_) {
    keys.push_back(key);
    count += voxels.size();
  }
  std::sort(keys.begin(), keys.end(), indexLess);
  const double size = reply.voxel_size, inv_size = 1.0 / size;
  std::vector<MapVoxel> all;
  all.reserve(count);
  for (const VoxelIndex& key : keys)
    for (const MapVoxel& v : blocks_.at(key)) {
      const Eigen::Vector3d c = (voxelIndex(v.point, inv_size).cast<double>().array() + 0.5) * size;
      if ((c - center).squaredNorm() <= radius * radius) all.push_back(v);
    }
  return LocalMap::fromVoxels(std::move(all), size, reply.p_hit, reply.map_epoch);
}

}  // namespace socc::odom
