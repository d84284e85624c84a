#pragma once
// The server's single semantic occupancy grid: the facade used by the LCM service.
// Data flows scan -> integrate() -> grid; grid -> queryChunk() -> ChunkVoxels (the service
// turns them into chunk_reply_t: the map knows nothing of the wire format).
// Not thread-safe: the service serialises access.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "socc/map/map_config.hpp"
#include "socc/point_cloud.hpp"
#include "socc/rgb_image.hpp"

namespace socc::map {

struct IntegrationResult {
  std::int32_t voxels_touched = 0;  // voxels changed by hits or misses
  std::int32_t voxels_hit = 0;
  std::int32_t voxels_freed = 0;  // voxels that turned free (statistics dropped)
  std::int32_t points_used = 0;   // points within [min_range, max_range]
};

struct ChunkQuery {
  enum class Shape { kBox, kSphere } shape = Shape::kSphere;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // sphere
  double radius = 0.0;
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();  // box
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  double occupancy_threshold = 0.5;
  // What to return per voxel (bit set; the values of chunk_request_t::FIELD_*).
  static constexpr std::int32_t kFeatures = 1;  // first point, normal, planarity, p_occ, label
  static constexpr std::int32_t kStats = 2;     // mean, covariance, count, log-odds, classes
  static constexpr std::int32_t kFree = 4;      // also the indices of free voxels
  static constexpr std::int32_t kIndex = 8;     // voxel index of each occupied voxel
  static constexpr std::int32_t kMoments = 16;  // with kFeatures: point counts, some moments
  std::int32_t fields = kFeatures;
  std::int32_t limit = 0;  // 0 = unlimited

  // Delta: the asker holds the complete answer to the sphere (center, radius) at map version
  // `version` of map epoch `epoch`. Blocks unchanged since then and wholly inside that sphere
  // are left out. Applies to spheres without kFree of the same map epoch; else ignored.
  struct Held {
    std::int64_t epoch = 0;
    std::int64_t version = 0;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0.0;
  };
  std::optional<Held> held;
};

/// The answer to a ChunkQuery, column-wise as chunk_reply_t holds it (docs/lcm.md): row k of
/// a multi-component field is component k of every voxel, entry i of each row is the i-th
/// occupied voxel; a field not asked for has empty rows.
struct ChunkVoxels {
  std::int32_t fields = 0;  // the ChunkQuery::k* bits answered
  bool truncated = false;   // the limit was reached: more voxels matched than returned
  std::int32_t num_occupied = 0;
  std::int64_t delta_of_version = -1;  // the query's held version when the answer is a delta
  // The occupied voxels come block by block: block b (key block_key[.][b]) holds the next
  // block_voxels[b]. Blocks with voxels are listed; a delta also lists changed blocks without.
  std::array<std::vector<std::int32_t>, 3> block_key;
  std::vector<std::int32_t> block_voxels;
  std::array<std::vector<std::int32_t>, 3> index;  // kIndex
  // kFeatures
  std::array<std::vector<float>, 3> first_point;    // map frame [m]
  std::array<std::vector<std::int16_t>, 3> normal;  // unit normal * 32767
  std::vector<float> planarity;
  std::vector<std::uint8_t> occupancy;  // round(p_occ * 255)
  std::vector<std::uint8_t> label;
  std::vector<std::uint8_t> label_prob;  // round(p_label * 255)
  // kMoments: each voxel's point count; the moments of those below chunk::kMomentsBelow points
  std::vector<std::uint32_t> point_count;
  std::array<std::vector<float>, 3> moment_mean;  // map frame [m]
  std::array<std::vector<float>, 6> moment_m2;    // xx xy xz yy yz zz [m^2]
  // kStats
  std::array<std::vector<float>, 3> mean;
  std::array<std::vector<float>, 6> covariance;  // xx xy xz yy yz zz
  std::vector<std::int32_t> count;
  std::vector<float> log_odds;
  std::vector<std::vector<float>> class_prob;           // [class][voxel]; no rows without kStats
  std::array<std::vector<std::int32_t>, 3> free_index;  // kFree
};

/// The occupied voxels of some blocks (the live view's stream, map_delta_t): block b (key
/// block_key[b], a block index) holds the next block_voxels[b] voxels; local is the voxel's
/// index in its block (x * 64 + y * 8 + z for 8-voxel blocks).
struct BlockVoxels {
  std::vector<std::array<std::int32_t, 3>> block_key;
  std::vector<std::int32_t> block_voxels;
  std::vector<std::int16_t> local;
  std::vector<std::uint8_t> occupancy;  // round(p_occ * 255)
  std::vector<std::uint8_t> label;
};

class BlockRegion;  // socc/map/block_region.hpp

struct MapStats {
  std::int64_t num_voxels = 0;
  std::int64_t num_occupied = 0;
  std::int64_t num_free = 0;
  std::int64_t num_blocks = 0;
  std::int64_t memory_bytes = 0;
  std::int64_t version = 0;
};

class SemanticOccupancyMap {
 public:
  explicit SemanticOccupancyMap(const MapConfig& config);
  ~SemanticOccupancyMap();
  SemanticOccupancyMap(SemanticOccupancyMap&&) noexcept;
  SemanticOccupancyMap& operator=(SemanticOccupancyMap&&) noexcept;

  const MapConfig& config() const;

  /// Empty when the cloud may be integrated (finite points, sizes consistent, labels < 20,
  /// point count and coordinates within the configured limits), otherwise the reason.
  std::string validate(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud) const;

  /// Integrates a cloud given in the sensor frame, sensor at sensor_pose (map frame):
  /// hits update statistics and log-odds; rays clear free space. Precondition:
  /// validate(sensor_pose, cloud) is empty (asserted, not checked again).
  IntegrationResult integrate(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud);
  /// The same, changing only the voxels of `within`'s blocks: the rays are traced in full, so
  /// those voxels get exactly what a whole integration gives them (a region rebuild).
  IntegrationResult integrate(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud,
                              const BlockRegion& within);
  /// The first form, also listing its footprint (as footprint() gives it) in `footprint`.
  IntegrationResult integrate(const Eigen::Isometry3d& sensor_pose, const LabeledCloud& cloud,
                              std::vector<Eigen::Vector3i>& footprint);

  /// The keys (socc/map/voxel_grid.hpp's BlockKey) of the blocks that integrate(sensor_pose,
  /// cloud) changes, those of the voxels its points hit and its rays cross, in key order
  /// (indexLess), leaving the map as it is: what a region rebuild erases and integrates again
  /// when the scan moves. Same precondition as integrate(); not const, as it works in the
  /// integrator's scratch memory.
  std::vector<Eigen::Vector3i> footprint(const Eigen::Isometry3d& sensor_pose,
                                         const LabeledCloud& cloud);

  /// Drops the region's blocks (they become unknown), as a region rebuild starts. A new epoch:
  /// no delta chunk can say that blocks vanished.
  void erase(const BlockRegion& region);

  /// A deep copy with the same contents and version and a new epoch (another map instance).
  SemanticOccupancyMap clone() const;

  /// The occupied (and, with kFree, free) voxels inside the query region (voxel centre
  /// inside; blocks in key order, so answers are deterministic). Throws std::invalid_argument
  /// for a malformed query (non-finite values, negative radius, box_min > box_max, threshold
  /// outside [0, 1], negative limit).
  ChunkVoxels queryChunk(const ChunkQuery& query) const;

  /// Keys of the blocks whose occupied voxels (at the map's threshold) may have changed after
  /// map version `since` (all blocks for since < 0), in key order.
  std::vector<std::array<std::int32_t, 3>> blocksChangedSince(std::int64_t since) const;
  /// The occupied voxels (at the map's threshold) of the given blocks; a block that does not
  /// exist (any more) is listed with no voxels.
  BlockVoxels occupiedInBlocks(const std::vector<std::array<std::int32_t, 3>>& keys) const;
  /// Voxels along a block's edge.
  static int blockDim();

  /// p_occ of the voxel holding p, or -1 when that voxel was never observed (unknown).
  double occupancyAt(const Eigen::Vector3d& p) const;

  MapStats stats() const;
  std::int64_t version() const;  // increases with every change
  /// Makes this map's version follow `previous` (the version of the map it replaces, e.g. a
  /// grid rebuilt at corrected poses): version() becomes greater than both.
  void continueVersion(std::int64_t previous);
  /// Random and non-zero, new with every map instance and clear(): a delta chunk is only valid
  /// against an answer of the same epoch.
  std::int64_t epoch() const;
  void clear();

  /// Snapshot: versioned, checksummed, written atomically (temp file + rename).
  /// metadata is an opaque blob stored alongside (the service keeps robot states there).
  void save(const std::filesystem::path& file, const std::string& metadata = {}) const;
  /// Loads a snapshot; on any error (missing, corrupt, wrong version or checksum) throws
  /// std::runtime_error and the current map stays unchanged.
  static SemanticOccupancyMap load(const std::filesystem::path& file,
                                   std::string* metadata = nullptr);

  /// Exports occupied voxels: OctoMap .bt (binary) or .ot (with colour = class colour),
  /// loadable by octovis; PCD (PointXYZRGBL: voxel centre, class colour, label).
  /// Returns the number of voxels exported. Throws std::runtime_error on I/O errors.
  std::int64_t exportOctomap(const std::filesystem::path& file, double occupancy_threshold) const;
  std::int64_t exportPcd(const std::filesystem::path& file, double occupancy_threshold) const;

  /// Top-down RGB image of [box_min, box_max] (x right, +y up), mode as render_request_t.
  /// pixel_size 0 = voxel size. Throws std::invalid_argument for a bad box, mode or threshold,
  /// or an image larger than 4096 x 4096.
  using Image = RgbImage;
  Image render(const Eigen::Vector3d& box_min, const Eigen::Vector3d& box_max, double pixel_size,
               int mode, double occupancy_threshold) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace socc::map
