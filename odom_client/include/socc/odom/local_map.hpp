#pragma once
// The registration target of one frame: the occupied voxels of a fetched map chunk, represented
// by their FIRST-INSERTED points (stable references, paper Sec. data association) with normal,
// planarity, occupancy and semantic label. Nearest-neighbour search is exact (KD-tree).
// A chunk may carry an overlay: voxels of the robot's own frames the chunk predates (their
// first points are the ones the server will keep), searched in a small second tree so the
// chunk's tree is built once (map_pipeline.hpp).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/point_cloud.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {

struct MapVoxel {
  Eigen::Vector3d point;   // first inserted point [m, map frame]
  Eigen::Vector3d normal;  // unit; zero when unknown (fewer than 5 points)
  float planarity = -1.f;  // tau = l3 / (l1 + l2 + l3); negative when unknown
  float occupancy = 0.f;   // p_occ
  std::uint8_t label = 0;  // argmax class
  float label_prob = 0.f;  // probability of that class
  // Of a voxel of few points, when known (a chunk with FIELD_MOMENTS, the client's own voxels):
  // its points so far, into which the client merges its next frames' points as the server will
  // (map_pipeline.hpp).
  std::optional<StoredMoments> moments;
};

/// Replacements of a chunk's voxels by id, e.g. after the client's own frames hit them again: a
/// slot per chunk voxel, so setting and finding one needs no hashing, and a map takes them as
/// one copy of two arrays.
class VoxelUpdates {
 public:
  bool empty() const { return voxels_.empty(); }
  /// The replacement of voxel id, or nullptr.
  const MapVoxel* find(std::size_t id) const {
    return id < slot_.size() && slot_[id] >= 0 ? &voxels_[static_cast<std::size_t>(slot_[id])]
                                               : nullptr;
  }
  void set(std::size_t id, MapVoxel v);

 private:
  std::vector<std::int32_t> slot_;  // by voxel id; -1: not replaced
  std::vector<MapVoxel> voxels_;
};

struct Neighbor {
  std::size_t index;
  double squared_distance;
};

struct NearestTwo {
  std::optional<Neighbor> nearest;
  double second_squared_distance;  // of the second nearest; the bound's square when none
};

class LocalMap {
 public:
  LocalMap();  // empty
  explicit LocalMap(std::vector<MapVoxel> voxels);
  ~LocalMap();
  LocalMap(const LocalMap&);  // cheap: the voxels and their search trees are shared
  LocalMap& operator=(const LocalMap&);
  LocalMap(LocalMap&&) noexcept;
  LocalMap& operator=(LocalMap&&) noexcept;

  /// Decodes a chunk with FIELD_FEATURES, keeping voxels with p_occ >= occupancy_threshold.
  /// Throws std::invalid_argument on a malformed reply (sizes, non-finite values, labels).
  static LocalMap fromChunk(const chunk_reply_t& chunk, double occupancy_threshold);
  /// The map of a chunk's decoded voxels (decodeChunkVoxels), with the chunk's voxel size, p_hit
  /// (voxel_size > 0) and map instance.
  static LocalMap fromVoxels(std::vector<MapVoxel> voxels, double voxel_size, double hit_occupancy,
                             std::int64_t epoch = 0);

  std::size_t size() const;
  bool empty() const { return size() == 0; }
  const MapVoxel& voxel(std::size_t i) const;

  /// The chunk's voxel size and the p_occ of a voxel hit once (0 when not made from a chunk).
  double voxelSize() const { return voxel_size_; }
  double hitOccupancy() const { return hit_occupancy_; }
  /// The chunk's map instance (chunk_reply_t::map_epoch): the frame of a pose registered
  /// against this map (0 when not made from a chunk).
  std::int64_t epoch() const { return epoch_; }

  struct Held {
    std::size_t id;
    bool moments;  // the voxel came with moments (it may have lost them in an update since)
  };
  /// The voxel at key (chunk or overlay), found without touching the voxels; none when this
  /// map was not made from a chunk (no voxel grid).
  std::optional<Held> find(const VoxelIndex& key) const;

  /// This map's chunk plus overlay, and with the chunk's voxels in updated replaced (by id; each
  /// keeps its first point, which the search tree holds), instead of any overlay and updates this
  /// map has; searched together. The chunk's voxels and search tree are shared, not copied.
  /// Overlay voxels follow the chunk's in id order.
  LocalMap withOverlay(std::vector<MapVoxel> overlay, const VoxelUpdates& updated = {}) const;

  /// The nearest first-inserted point within max_distance of query, if any (exact).
  std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double max_distance) const;
  /// The same, and the distance of the second nearest point within max_distance.
  NearestTwo nearestTwo(const Eigen::Vector3d& query, double max_distance) const;

 private:
  class Layer;
  std::shared_ptr<const Layer> base_;            // the chunk's voxels
  std::shared_ptr<const Layer> overlay_;         // none: no overlay
  std::shared_ptr<const VoxelUpdates> updated_;  // none: the chunk's voxels as sent
  double voxel_size_ = 0.0;                      // from the chunk; 0: not a chunk
  double hit_occupancy_ = 0.0;
  std::int64_t epoch_ = 0;
};

/// Every voxel of a chunk with FIELD_FEATURES, in the reply's order. Throws
/// std::invalid_argument on a malformed reply (sizes, non-finite values, labels, voxel size).
std::vector<MapVoxel> decodeChunkVoxels(const chunk_reply_t& chunk);

/// p_occ of v at or above occupancy_threshold (as decoded from the reply's byte).
bool occupiedAt(const MapVoxel& v, double occupancy_threshold);

/// Share of cloud's points (sensor frame) within max_distance of map at pose: how much of a scan
/// a pose explains. 0 for an empty cloud.
double fractionNearMap(const std::vector<Eigen::Vector3f>& points, const LocalMap& map,
                       const Eigen::Isometry3d& pose, double max_distance);

/// Planar voxel: tau known (>= 0) and below the threshold, with a valid normal.
inline bool isPlanar(const MapVoxel& v, double planarity_threshold) {
  return v.planarity >= 0.f && v.planarity < planarity_threshold && v.normal.squaredNorm() > 0.5;
}

}  // namespace socc::odom
