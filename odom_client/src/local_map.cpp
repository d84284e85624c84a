#include "socc/odom/local_map.hpp"

#include <tbb/parallel_invoke.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <stdexcept>
#include <string>

#include "socc/chunk_features.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/labels.hpp"
#include "socc/voxel.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::odom {
namespace {

// Result set keeping only the nearest point closer than a bound; the bound prunes the search.
class NearestWithin {
 public:
  explicit NearestWithin(double bound2) : best_(bound2) {}
  bool full() const { return true; }
  bool addPoint(double dist2, std::uint32_t index) {
    if (dist2 < best_) {
      best_ = dist2;
      index_ = index;
    }
    return true;
  }
  double worstDist() const { return best_; }
  std::optional<Neighbor> result() const {
    if (index_ == kNone) return std::nullopt;
    return Neighbor{index_, best_};
  }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  double best_;
  std::uint32_t index_ = kNone;
};

// Result set keeping the two nearest points closer than a bound: the second's distance bounds
// how far the query may move with the same nearest point (registration's correspondence reuse).
class TwoNearestWithin {
 public:
  explicit TwoNearestWithin(double bound2) : first_(bound2), second_(bound2) {}
  bool full() const { return true; }
  bool addPoint(double dist2, std::uint32_t index) {
    if (dist2 < first_) {
      second_ = first_;
      first_ = dist2;
      index_ = index;
    } else if (dist2 < second_) {
      second_ = dist2;
    }
    return true;
  }
  double worstDist() const { return second_; }
  NearestTwo result(std::size_t offset) const {
    NearestTwo out;
    if (index_ != kNone) out.nearest = Neighbor{index_ + offset, first_};
    out.second_squared_distance = second_;
    return out;
  }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  double first_;
  double second_;
  std::uint32_t index_ = kNone;
};

[[noreturn]] void malformed(const std::string& why) {
  throw std::invalid_argument("malformed chunk reply: " + why);
}

// FIELD_MOMENTS: the moments of the voxels of fewer points than moments_below, in their order.
void decodeMoments(const chunk_reply_t& chunk, std::vector<MapVoxel>& voxels) {
  if (chunk.n_counts != static_cast<std::int32_t>(voxels.size()))
    malformed("n_counts (" + std::to_string(chunk.n_counts) + ") != num_voxels");
  const auto with = std::count_if(chunk.point_count.begin(), chunk.point_count.end(),
                                  [&](std::uint8_t c) { return c < chunk.moments_below; });
  if (chunk.n_moments != with)
    malformed("n_moments (" + std::to_string(chunk.n_moments) + ") != voxels below " +
              std::to_string(chunk.moments_below) + " points (" + std::to_string(with) + ")");
  std::size_t j = 0;
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    if (chunk.point_count[i] >= chunk.moments_below) continue;
    StoredMoments m;
    m.count = chunk.point_count[i];
    for (int a = 0; a < 3; ++a)
      m.mean[a] = static_cast<float>(
          voxels[i].point[a] + chunk::decodeMeanOffset(chunk.moment_mean[a][j], chunk.voxel_size));
    for (int k = 0; k < 6; ++k)
      m.m2[k] = static_cast<float>(
          chunk::decodeScatter(chunk.moment_m2[k][j], m.count, chunk.voxel_size));
    voxels[i].moments = m;
    ++j;
  }
}

}  // namespace

// One searched set of voxels, a chunk's or an overlay's, with its search tree and (on a voxel
// grid) its voxels' keys. Immutable once built, so maps share it.
class LocalMap::Layer {
 public:
  Layer(std::vector<MapVoxel> v, std::size_t first_id, double voxel_size)
      : voxels(std::move(v)),
        first_id_(first_id),
        points_(firstPoints(voxels)),
        adaptor_{&points_},
        tree_(3, adaptor_,
              nanoflann::KDTreeSingleIndexAdaptorParams(
                  10, nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex)) {
    if (voxel_size <= 0.0) {
      tree_.buildIndex();
      return;
    }
    // Independent, and a chunk's are on the path of the frame that waits for it: in parallel.
    tbb::parallel_invoke([this] { tree_.buildIndex(); },
                         [this, voxel_size] { indexKeys(voxel_size); });
  }
  Layer(const Layer&) = delete;  // the tree refers to adaptor_
  Layer& operator=(const Layer&) = delete;

  std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double bound2) const {
    if (voxels.empty()) return std::nullopt;
    NearestWithin result(bound2);
    tree_.findNeighbors(result, query.data(), nanoflann::SearchParams());
    std::optional<Neighbor> n = result.result();
    if (n) n->index += first_id_;
    return n;
  }
  NearestTwo nearestTwo(const Eigen::Vector3d& query, double bound2) const {
    if (voxels.empty()) return NearestTwo{std::nullopt, bound2};
    TwoNearestWithin result(bound2);
    tree_.findNeighbors(result, query.data(), nanoflann::SearchParams());
    return result.result(first_id_);
  }
  /// The voxel at key, if this layer holds it.
  std::optional<Held> find(const VoxelIndex& key) const {
    const auto it = keys_.find(key);
    if (it == keys_.end()) return std::nullopt;
    return Held{first_id_ + it->second.index, it->second.moments};
  }

  const std::vector<MapVoxel> voxels;

 private:
  void indexKeys(double voxel_size) {
    const double inv_size = 1.0 / voxel_size;
    keys_.reserve(voxels.size());
    for (std::size_t i = 0; i < voxels.size(); ++i)
      keys_.emplace(voxelIndex(voxels[i].point, inv_size),
                    Key{static_cast<std::uint32_t>(i), voxels[i].moments.has_value()});
  }
  // The voxels' first-inserted points, packed: the tree's build and searches read 24 bytes a
  // point instead of a whole MapVoxel's cache lines.
  static std::vector<Eigen::Vector3d> firstPoints(const std::vector<MapVoxel>& voxels) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(voxels.size());
    for (const MapVoxel& v : voxels) out.push_back(v.point);
    return out;
  }
  // nanoflann dataset adaptor over the voxels' first-inserted points.
  struct PointsAdaptor {
    const std::vector<Eigen::Vector3d>* points;
    std::size_t kdtree_get_point_count() const { return points->size(); }
    double kdtree_get_pt(std::uint32_t i, std::size_t dim) const { return (*points)[i][dim]; }
    template <typename Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using KdTree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                          PointsAdaptor, 3, std::uint32_t>;

  std::size_t first_id_;  // ids of this layer's voxels start here
  const std::vector<Eigen::Vector3d> points_;
  PointsAdaptor adaptor_;
  KdTree tree_;
  struct Key {
    std::uint32_t index;
    bool moments;
  };
  tsl::robin_map<VoxelIndex, Key, VoxelIndexHash> keys_;  // on a voxel grid
};

void VoxelUpdates::set(std::size_t id, MapVoxel v) {
  if (id >= slot_.size()) slot_.resize(id + 1, -1);
  if (slot_[id] >= 0) {
    voxels_[static_cast<std::size_t>(slot_[id])] = std::move(v);
    return;
  }
  slot_[id] = static_cast<std::int32_t>(voxels_.size());
  voxels_.push_back(std::move(v));
}

LocalMap::LocalMap() : LocalMap(std::vector<MapVoxel>{}) {}
LocalMap::LocalMap(std::vector<MapVoxel> voxels)
    : base_(std::make_shared<const Layer>(std::move(voxels), 0, 0.0)) {}
LocalMap::~LocalMap() = default;
LocalMap::LocalMap(const LocalMap&) = default;
LocalMap& LocalMap::operator=(const LocalMap&) = default;
LocalMap::LocalMap(LocalMap&&) noexcept = default;
LocalMap& LocalMap::operator=(LocalMap&&) noexcept = default;

std::size_t LocalMap::size() const {
  return base_->voxels.size() + (overlay_ ? overlay_->voxels.size() : 0);
}
const MapVoxel& LocalMap::voxel(std::size_t i) const {
  const std::size_t n = base_->voxels.size();
  if (i >= n) return overlay_->voxels[i - n];
  if (updated_)
    if (const MapVoxel* v = updated_->find(i)) return *v;
  return base_->voxels[i];
}

std::optional<Neighbor> LocalMap::nearest(const Eigen::Vector3d& query, double max_distance) const {
  if (empty() || !query.allFinite()) return std::nullopt;
  const double bound2 = max_distance * max_distance;
  std::optional<Neighbor> best = base_->nearest(query, bound2);
  if (overlay_) {
    const std::optional<Neighbor> o =
        overlay_->nearest(query, best ? best->squared_distance : bound2);
    if (o) best = o;
  }
  return best;
}

NearestTwo LocalMap::nearestTwo(const Eigen::Vector3d& query, double max_distance) const {
  const double bound2 = max_distance * max_distance;
  if (empty() || !query.allFinite()) return NearestTwo{std::nullopt, bound2};
  NearestTwo best = base_->nearestTwo(query, bound2);
  if (!overlay_) return best;
  const NearestTwo o = overlay_->nearestTwo(query, best.second_squared_distance);
  // The two smallest of the four distances (o's are below best's second, or o found none).
  if (!o.nearest) return best;
  if (!best.nearest || o.nearest->squared_distance < best.nearest->squared_distance) {
    const double second = best.nearest ? best.nearest->squared_distance : bound2;
    return NearestTwo{o.nearest, std::min(second, o.second_squared_distance)};
  }
  return NearestTwo{best.nearest, o.nearest->squared_distance};
}

std::optional<LocalMap::Held> LocalMap::find(const VoxelIndex& key) const {
  if (voxel_size_ <= 0.0) return std::nullopt;
  if (std::optional<Held> held = base_->find(key)) return held;
  return overlay_ ? overlay_->find(key) : std::nullopt;
}

LocalMap LocalMap::withOverlay(std::vector<MapVoxel> overlay, const VoxelUpdates& updated) const {
  LocalMap out = *this;
  out.overlay_.reset();
  out.updated_.reset();
  if (!overlay.empty())
    out.overlay_ =
        std::make_shared<const Layer>(std::move(overlay), base_->voxels.size(), voxel_size_);
  if (!updated.empty()) out.updated_ = std::make_shared<const VoxelUpdates>(updated);
  return out;
}

std::vector<MapVoxel> decodeChunkVoxels(const chunk_reply_t& chunk) {
  const int n = chunk.num_voxels;
  if (n < 0) malformed("negative num_voxels");
  if (!(std::isfinite(chunk.voxel_size) && chunk.voxel_size > 0.0))
    malformed("voxel_size " + std::to_string(chunk.voxel_size));
  if (!(chunk.p_hit >= 0.f && chunk.p_hit <= 1.f)) malformed("p_hit outside [0, 1]");
  if (n > 0 && (!(chunk.fields & chunk_request_t::FIELD_FEATURES) || chunk.n_features != n))
    malformed("FIELD_FEATURES missing or n_features (" + std::to_string(chunk.n_features) +
              ") != num_voxels (" + std::to_string(n) + ")");
  if (const std::string why = wire::checkArrays(chunk); !why.empty()) malformed(why);

  if (const std::string why = chunk::checkBlocks(chunk); !why.empty()) malformed(why);

  // First points from their blocks' corners; the other rows ([component][voxel]) in one pass.
  const std::vector<Eigen::Vector3d> points = chunk::firstPoints(chunk);
  std::vector<MapVoxel> voxels(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    MapVoxel& v = voxels[i];
    v.occupancy = chunk.occupancy[i] / 255.f;
    v.point = points[i];
    v.planarity = static_cast<float>(chunk::decodePlanarity(chunk.planarity[i]));
    v.normal = v.planarity >= 0.f ? chunk::decodeNormal(chunk.normal[0][i], chunk.normal[1][i])
                                  : Eigen::Vector3d::Zero();
    v.label = chunk.label[i];
    if (!isValidClass(v.label))
      malformed("label " + std::to_string(v.label) + " at voxel " + std::to_string(i));
    v.label_prob = chunk.label_prob[i] / 255.f;
  }
  if (chunk.fields & chunk_request_t::FIELD_MOMENTS) decodeMoments(chunk, voxels);
  return voxels;
}

bool occupiedAt(const MapVoxel& v, double occupancy_threshold) {
  return v.occupancy + 1e-6f >= occupancy_threshold;  // bytes of p_occ: no false rounding misses
}

LocalMap LocalMap::fromChunk(const chunk_reply_t& chunk, double occupancy_threshold) {
  std::vector<MapVoxel> voxels = decodeChunkVoxels(chunk);
  voxels.erase(
      std::remove_if(voxels.begin(), voxels.end(),
                     [&](const MapVoxel& v) { return !occupiedAt(v, occupancy_threshold); }),
      voxels.end());
  return fromVoxels(std::move(voxels), chunk.voxel_size, chunk.p_hit, chunk.map_epoch);
}

LocalMap LocalMap::fromVoxels(std::vector<MapVoxel> voxels, double voxel_size, double hit_occupancy,
                              std::int64_t epoch) {
  LocalMap map;
  map.base_ = std::make_shared<const Layer>(std::move(voxels), 0, voxel_size);
  map.voxel_size_ = voxel_size;
  map.hit_occupancy_ = hit_occupancy;
  map.epoch_ = epoch;
  return map;
}
double fractionNearMap(const std::vector<Eigen::Vector3f>& points, const LocalMap& map,
                       const Eigen::Isometry3d& pose, double max_distance) {
  if (points.empty()) return 0.0;
  std::size_t n = 0;
  for (const Eigen::Vector3f& p : points)
    n += map.nearest(pose * p.cast<double>(), max_distance) ? 1 : 0;
  return static_cast<double>(n) / static_cast<double>(points.size());
}

}  // namespace socc::odom
