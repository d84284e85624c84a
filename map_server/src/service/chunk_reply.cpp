#include "service/chunk_reply.hpp"

#include <iterator>
#include <utility>

#include "socc/chunk_request_t.hpp"
#include "socc/map/voxel_grid.hpp"

namespace socc::service {
namespace {

// The map's field bits are the wire's: requests pass them through unchanged.
static_assert(map::ChunkQuery::kFeatures == chunk_request_t::FIELD_FEATURES &&
              map::ChunkQuery::kStats == chunk_request_t::FIELD_STATS &&
              map::ChunkQuery::kFree == chunk_request_t::FIELD_FREE &&
              map::ChunkQuery::kIndex == chunk_request_t::FIELD_INDEX);

template <typename T, std::size_t N>
std::vector<std::vector<T>> rowsOf(std::array<std::vector<T>, N>&& rows) {
  return {std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end())};
}

}  // namespace

void toChunkReply(map::ChunkVoxels&& voxels, chunk_reply_t& out) {
  out.fields = voxels.fields;
  out.truncated = voxels.truncated;
  out.num_voxels = voxels.num_occupied;
  out.delta_of_version = voxels.delta_of_version;
  out.block_dim = map::kBlockDim;
  out.block = rowsOf(std::move(voxels.block_key));
  out.block_voxels = std::move(voxels.block_voxels);
  out.n_blocks = static_cast<std::int32_t>(out.block_voxels.size());
  out.index = rowsOf(std::move(voxels.index));
  out.first_point = rowsOf(std::move(voxels.first_point));
  out.normal = rowsOf(std::move(voxels.normal));
  out.planarity = std::move(voxels.planarity);
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
  out.p_hit = static_cast<float>(map.config().p_hit);
}

chunk_reply_t queryChunkReply(const map::SemanticOccupancyMap& map, const map::ChunkQuery& query) {
  chunk_reply_t reply{};
  toChunkReply(map.queryChunk(query), reply);
  setMapInfo(map, reply);
  return reply;
}

}  // namespace socc::service
