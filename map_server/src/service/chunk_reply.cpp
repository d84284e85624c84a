#include "service/chunk_reply.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

#include "socc/chunk_features.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::service {
namespace {

// The map's field bits are the wire's: requests pass them through unchanged.
static_assert(map::ChunkQuery::kFeatures == chunk_request_t::FIELD_FEATURES &&
              map::ChunkQuery::kStats == chunk_request_t::FIELD_STATS &&
              map::ChunkQuery::kFree == chunk_request_t::FIELD_FREE &&
              map::ChunkQuery::kIndex == chunk_request_t::FIELD_INDEX &&
              map::ChunkQuery::kMoments == chunk_request_t::FIELD_MOMENTS);

template <typename T, std::size_t N>
std::vector<std::vector<T>> rowsOf(std::array<std::vector<T>, N>&& rows) {
  return {std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end())};
}

// FIELD_FEATURES in the compact encoding (socc/chunk_features.hpp): first points as offsets from
// their block's corner, octahedral normals, planarity in a byte.
void encodeFeatures(const map::ChunkVoxels& v, double voxel_size, chunk_reply_t& out) {
  const std::size_t n = v.planarity.size();
  out.first_point.assign(3, std::vector<std::int16_t>(n));
  out.normal.assign(2, std::vector<std::int16_t>(n));
  out.planarity.resize(n);
  if (n == 0) return;  // FIELD_FEATURES not asked for
  const double block_size = map::kBlockDim * voxel_size;
  std::size_t i = 0;
  for (std::size_t b = 0; b < v.block_voxels.size(); ++b) {
    const Eigen::Vector3d corner = chunk::blockCorner(
        {v.block_key[0][b], v.block_key[1][b], v.block_key[2][b]}, map::kBlockDim, voxel_size);
    for (std::int32_t k = 0; k < v.block_voxels[b]; ++k, ++i) {
      for (int a = 0; a < 3; ++a)
        out.first_point[a][i] = chunk::encodeOffset(v.first_point[a][i] - corner[a], block_size);
      const double tau = v.planarity[i];
      out.planarity[i] = chunk::encodePlanarity(tau);
      const Eigen::Vector3d normal(v.normal[0][i], v.normal[1][i], v.normal[2][i]);
      const auto octahedral = chunk::encodeNormal(tau >= 0.0 ? normal : Eigen::Vector3d::Zero());
      out.normal[0][i] = octahedral[0];
      out.normal[1][i] = octahedral[1];
    }
  }
}

// FIELD_MOMENTS in the compact encoding (socc/chunk_features.hpp).
void encodeMoments(const map::ChunkVoxels& v, double voxel_size, chunk_reply_t& out) {
  const std::size_t n = v.point_count.size();
  out.n_counts = static_cast<std::int32_t>(n);
  out.point_count.resize(n);
  out.moments_below = static_cast<std::uint8_t>(chunk::kMomentsBelow);
  const std::size_t m = v.moment_m2[0].size();
  out.n_moments = static_cast<std::int32_t>(m);
  out.moment_mean.assign(m == 0 ? 0 : 3, std::vector<std::int16_t>(m));
  out.moment_m2.assign(m == 0 ? 0 : 6, std::vector<std::int16_t>(m));
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out.point_count[i] = static_cast<std::uint8_t>(std::min<std::uint32_t>(v.point_count[i], 255));
    if (v.point_count[i] >= chunk::kMomentsBelow) continue;
    for (int a = 0; a < 3; ++a)
      out.moment_mean[a][j] =
          chunk::encodeMeanOffset(double{v.moment_mean[a][j]} - v.first_point[a][i], voxel_size);
    for (int k = 0; k < 6; ++k)
      out.moment_m2[k][j] = chunk::encodeScatter(v.moment_m2[k][j], v.point_count[i], voxel_size);
    ++j;
  }
}

}  // namespace

void toChunkReply(map::ChunkVoxels&& voxels, double voxel_size, chunk_reply_t& out) {
  out.fields = voxels.fields;
  out.truncated = voxels.truncated;
  out.num_voxels = voxels.num_occupied;
  out.delta_of_version = voxels.delta_of_version;
  encodeFeatures(voxels, voxel_size, out);  // before the block lists move out
  encodeMoments(voxels, voxel_size, out);
  out.block = rowsOf(std::move(voxels.block_key));
  out.block_voxels = std::move(voxels.block_voxels);
  out.n_blocks = static_cast<std::int32_t>(out.block_voxels.size());
  out.index = rowsOf(std::move(voxels.index));
  out.occupancy = std::move(voxels.occupancy);
  out.label = std::move(voxels.label);
  out.label_prob = std::move(voxels.label_prob);
  out.mean = rowsOf(std::move(voxels.mean));
  out.covariance = rowsOf(std::move(voxels.covariance));
  out.count = std::move(voxels.count);
  out.log_odds = std::move(voxels.log_odds);
  out.class_prob = std::move(voxels.class_prob);
  out.free_index = rowsOf(std::move(voxels.free_index));
  out.n_index = static_cast<std::int32_t>(out.index[0].size());
  out.n_features = static_cast<std::int32_t>(out.occupancy.size());
  out.n_stats = static_cast<std::int32_t>(out.count.size());
  out.num_classes = static_cast<std::int32_t>(out.class_prob.size());
  out.n_free = static_cast<std::int32_t>(out.free_index[0].size());
}

void setMapInfo(const map::SemanticOccupancyMap& map, chunk_reply_t& out) {
  out.voxel_size = map.config().voxel_size;
  out.map_version = map.version();
  out.map_epoch = map.epoch();
  out.block_dim = map::kBlockDim;
  out.p_hit = static_cast<float>(map.config().p_hit);
}

chunk_reply_t queryChunkReply(const map::SemanticOccupancyMap& map, const map::ChunkQuery& query) {
  chunk_reply_t reply{};
  toChunkReply(map.queryChunk(query), map.config().voxel_size, reply);
  setMapInfo(map, reply);
  return reply;
}

}  // namespace socc::service
