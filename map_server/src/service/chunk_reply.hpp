#pragma once
// The wire form of the map's answer to a chunk query: the one place where ChunkVoxels become
// chunk_reply_t (GET_CHUNK, and tests that feed a LocalMap from an in-process map).
#include "socc/chunk_reply_t.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::service {

/// Moves the voxel columns into out (features encoded: socc/chunk_features.hpp, with the map's
/// voxel_size) and sets its counts; the map's fields (setMapInfo) and the header are left to the
/// caller.
void toChunkReply(map::ChunkVoxels&& voxels, double voxel_size, chunk_reply_t& out);

/// Sets what every chunk reply says of the map: voxel_size, map_version, map_epoch, block_dim,
/// p_hit.
void setMapInfo(const map::SemanticOccupancyMap& map, chunk_reply_t& out);

/// The whole reply of a successful query (columns and setMapInfo).
chunk_reply_t queryChunkReply(const map::SemanticOccupancyMap& map, const map::ChunkQuery& query);

}  // namespace socc::service
