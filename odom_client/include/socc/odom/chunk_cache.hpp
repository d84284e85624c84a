#pragma once
// The client's copy of the map around the robot, kept up to date by delta chunks (docs/lcm.md
// "Delta chunks"): each GET_CHUNK says which answer the client holds (map epoch, version,
// sphere) and the server sends only the blocks that changed since, or that were not wholly
// inside the sphere held. The map built from the copy equals the one a complete chunk of the
// same sphere gives (same voxels, same order). Soft state: reset(), a truncated reply or one of
// another map epoch make the next request a complete one.
#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/odom/local_map.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {

/// GET_CHUNK of the sphere's voxels with p_occ >= occupancy_threshold, with FIELD_FEATURES: the
/// registration target's request. with_moments: also FIELD_MOMENTS, for a target the client
/// merges its own frames into (map_pipeline.hpp).
chunk_request_t featureChunkRequest(const Eigen::Vector3d& center, double radius,
                                    double occupancy_threshold, bool with_moments = false);

class ChunkCache {
 public:
  explicit ChunkCache(double occupancy_threshold) : occupancy_threshold_(occupancy_threshold) {}

  /// GET_CHUNK (FIELD_FEATURES, FIELD_MOMENTS) of the sphere: a delta on what is held, if any.
  chunk_request_t request(const Eigen::Vector3d& center, double radius) const;

  /// Applies the reply to request(center, radius); returns the map of the whole sphere.
  /// Throws std::invalid_argument on a malformed reply (the cache is reset then).
  LocalMap apply(const chunk_reply_t& reply, const Eigen::Vector3d& center, double radius);

  void reset();

 private:
  struct Held {
    std::int64_t epoch = 0;
    std::int64_t version = 0;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0.0;
  };

  void replaceBlocks(const chunk_reply_t& reply, std::vector<MapVoxel> voxels);
  void dropBlocksOutside(const Eigen::Vector3d& center, double radius, double block_size);
  LocalMap build(const Eigen::Vector3d& center, double radius, const chunk_reply_t& reply) const;

  double occupancy_threshold_;
  std::optional<Held> held_;
  tsl::robin_map<VoxelIndex, std::vector<MapVoxel>, VoxelIndexHash> blocks_;  // by block key
};

}  // namespace socc::odom
