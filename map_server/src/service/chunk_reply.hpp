#pragma once
// The wire form of the map's answer to a chunk query: the one place where ChunkVoxels become
// chunk_reply_t (GET_CHUNK, and tests that feed a LocalMap from an in-process map).
#include "socc/chunk_reply_t.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::service {

/// Moves the voxel columns into out and sets its counts; voxel_size, map_version and the
/// header are left to the caller.
void toChunkReply(map::ChunkVoxels&& voxels, chunk_reply_t& out);

/// out.voxel_size and out.map_version set from map: the whole reply of a successful query.
chunk_reply_t queryChunkReply(const map::SemanticOccupancyMap& map, const map::ChunkQuery& query);

}  // namespace socc::service
