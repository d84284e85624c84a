// SemanticOccupancyMap::queryChunk: voxels of a box or sphere in the column layout of
// ChunkVoxels. Blocks are visited in lexicographic key order and voxels in local order, so
// answers are deterministic (identical after a snapshot round trip).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "map_impl.hpp"
#include "occupied_test.hpp"
#include "region.hpp"
#include "socc/chunk_features.hpp"
#include "socc/map/voxel_features.hpp"
#include "socc/rounding.hpp"

namespace socc::map {
namespace {

std::uint8_t toByte(double p) {
  return static_cast<std::uint8_t>(roundHalfAway(std::clamp(p, 0.0, 1.0) * 255.0));
}

void checkQuery(const ChunkQuery& q) {
  if (q.shape == ChunkQuery::Shape::kSphere) {
    if (!q.center.allFinite() || !std::isfinite(q.radius) || q.radius < 0.0)
      throw std::invalid_argument("chunk query: sphere needs a finite centre and radius >= 0");
  } else if (!q.box_min.allFinite() || !q.box_max.allFinite() ||
             (q.box_max.array() < q.box_min.array()).any()) {
    throw std::invalid_argument("chunk query: box needs finite corners with box_min <= box_max");
  }
  if (!(q.occupancy_threshold >= 0.0 && q.occupancy_threshold <= 1.0))
    throw std::invalid_argument("chunk query: occupancy_threshold must be in [0, 1]");
  if (q.limit < 0) throw std::invalid_argument("chunk query: limit must be >= 0");
}

// Appends one voxel's 3 components to a [component][voxel] field (values not deduced: the
// row type decides).
template <typename T>
void push3(std::array<std::vector<T>, 3>& rows, typename std::vector<T>::value_type x,
           typename std::vector<T>::value_type y, typename std::vector<T>::value_type z) {
  rows[0].push_back(x);
  rows[1].push_back(y);
  rows[2].push_back(z);
}

// An occupied voxel of the answer, chosen in order (limit, block lists); its fields are written
// afterwards, in parallel: features (an eigen-decomposition each) are most of a query's time.
struct Chosen {
  VoxelIndex v;
  Eigen::Vector3d centre;
  float log_odds;
  const VoxelStats* stats;  // null: occupied without statistics
  std::int32_t moment_row;  // its row of the moment columns; -1: none
};

// Sizes the columns of fields for n occupied voxels, `moments` of them with moment rows.
void sizeColumns(ChunkVoxels& out, std::size_t n, std::size_t moments, std::int32_t fields) {
  const auto size3 = [](auto& rows, std::size_t k) {
    for (auto& row : rows) row.resize(k);
  };
  if (fields & ChunkQuery::kIndex) size3(out.index, n);
  if (fields & ChunkQuery::kFeatures) {
    size3(out.first_point, n);
    size3(out.normal, n);
    out.planarity.resize(n);
    out.occupancy.resize(n);
    out.label.resize(n);
    out.label_prob.resize(n);
  }
  if ((fields & ChunkQuery::kFeatures) && (fields & ChunkQuery::kMoments)) {
    out.point_count.resize(n);
    size3(out.moment_mean, moments);
    size3(out.moment_m2, moments);
  }
  if (fields & ChunkQuery::kStats) {
    size3(out.mean, n);
    size3(out.covariance, n);
    out.count.resize(n);
    out.log_odds.resize(n);
    size3(out.class_prob, n);
  }
}

// Writes voxel i's fields into the sized columns.
void writeOccupied(ChunkVoxels& out, std::size_t i, const Chosen& c, std::int32_t fields) {
  if (fields & ChunkQuery::kIndex)
    for (int a = 0; a < 3; ++a) out.index[a][i] = c.v[a];
  const VoxelStats empty;
  const VoxelStats& s = c.stats != nullptr ? *c.stats : empty;
  const Eigen::Vector3f centref = c.centre.cast<float>();
  if (fields & ChunkQuery::kFeatures) {
    // Occupied without statistics (only below the map's threshold): the centre stands in.
    for (int a = 0; a < 3; ++a) out.first_point[a][i] = c.stats ? s.first_point[a] : centref[a];
    const VoxelFeatures f = computeFeatures(s);
    const auto q = [](double x) { return static_cast<std::int16_t>(roundHalfAway(x * 32767.0)); };
    for (int a = 0; a < 3; ++a) out.normal[a][i] = q(f.normal[a]);
    out.planarity[i] = static_cast<float>(f.planarity);
    out.occupancy[i] = toByte(probability(c.log_odds));
    out.label[i] = s.label;
    out.label_prob[i] = s.has_semantics ? toByte(s.prob(s.label)) : 0;
    if (fields & ChunkQuery::kMoments) out.point_count[i] = s.count;
    if (c.moment_row >= 0) {
      const auto j = static_cast<std::size_t>(c.moment_row);
      for (int a = 0; a < 3; ++a) out.moment_mean[a][j] = c.stats ? s.mean[a] : centref[a];
      for (int k = 0; k < 6; ++k) out.moment_m2[k][j] = s.m2[k];
    }
  }
  if (fields & ChunkQuery::kStats) {
    for (int a = 0; a < 3; ++a) out.mean[a][i] = c.stats ? s.mean[a] : centref[a];
    const Eigen::Matrix3d cov = s.covariance();
    const double upper[6] = {cov(0, 0), cov(0, 1), cov(0, 2), cov(1, 1), cov(1, 2), cov(2, 2)};
    for (int k = 0; k < 6; ++k) out.covariance[k][i] = static_cast<float>(upper[k]);
    out.count[i] = static_cast<std::int32_t>(s.count);
    out.log_odds[i] = c.log_odds;
    for (int k = 0; k < kNumClasses; ++k) out.class_prob[k][i] = s.prob(k);
  }
}

// Squared distance from p to the farthest corner of the box [lo, hi].
double farthestCorner(const Eigen::Vector3d& p, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi) {
  return (p - lo).cwiseAbs().cwiseMax((p - hi).cwiseAbs()).squaredNorm();
}

// The query's box or sphere: the voxel-index bounds to visit and the test of a voxel centre.
class QueryRegion {
 public:
  QueryRegion(const ChunkQuery& q, double voxel_size)
      : q_(q), sphere_(q.shape == ChunkQuery::Shape::kSphere), r2_(q.radius * q.radius) {
    const Eigen::Vector3d rmin = sphere_ ? (q.center.array() - q.radius).matrix() : q.box_min;
    const Eigen::Vector3d rmax = sphere_ ? (q.center.array() + q.radius).matrix() : q.box_max;
    box = IndexBox::of(rmin, rmax, voxel_size);
  }

  bool covers(const VoxelIndex& v) const {
    return (v.array() >= box.lo.array()).all() && (v.array() <= box.hi.array()).all();
  }
  bool contains(const Eigen::Vector3d& c) const {
    if (sphere_) return (c - q_.center).squaredNorm() <= r2_;
    return (c.array() >= q_.box_min.array()).all() && (c.array() <= q_.box_max.array()).all();
  }
  /// Every voxel centre of block key is inside: no test per voxel.
  bool containsBlock(const BlockKey& key, const Grid& grid) const {
    const Eigen::Vector3d lo = grid.centre(voxelOf(key, 0));
    const Eigen::Vector3d hi = grid.centre(voxelOf(key, kBlockVoxels - 1));
    if (!sphere_) return contains(lo) && contains(hi);
    return farthestCorner(q_.center, lo, hi) <= r2_;
  }

  IndexBox box;

 private:
  const ChunkQuery& q_;
  bool sphere_;
  double r2_;
};

// The blocks a delta may leave out: unchanged since the held answer and with every voxel centre
// inside the held sphere (so the asker holds all of their voxels).
class HeldBlocks {
 public:
  HeldBlocks(const ChunkQuery& q, std::int64_t epoch, const Grid& grid,
             double map_occupancy_threshold)
      : grid_(grid), occupied_only_(q.occupancy_threshold >= map_occupancy_threshold) {
    active_ = q.held && q.held->epoch == epoch && q.shape == ChunkQuery::Shape::kSphere &&
              !(q.fields & ChunkQuery::kFree);
    if (active_) held_ = *q.held;
  }
  bool active() const { return active_; }
  std::int64_t version() const { return held_.version; }
  // At the map's threshold or above, a change only to voxels below it is invisible.
  bool changed(const Block& block) const {
    return (occupied_only_ ? block.occupied_version : block.version) > held_.version;
  }
  bool held(const BlockKey& key, const Block& block) const {
    if (!active_ || changed(block)) return false;
    // The farthest voxel centre of the block from the held sphere's centre.
    const Eigen::Vector3d lo = grid_.centre(voxelOf(key, 0));
    const Eigen::Vector3d hi = grid_.centre(voxelOf(key, kBlockVoxels - 1));
    const Eigen::Vector3d far =
        (held_.center - lo).cwiseAbs().cwiseMax((held_.center - hi).cwiseAbs());
    return far.squaredNorm() <= held_.radius * held_.radius;
  }

 private:
  const Grid& grid_;
  bool occupied_only_;
  bool active_ = false;
  ChunkQuery::Held held_;
};

}  // namespace

ChunkVoxels SemanticOccupancyMap::queryChunk(const ChunkQuery& query) const {
  checkQuery(query);
  const Impl& m = *impl_;
  const QueryRegion region(query, m.config.voxel_size);
  std::int32_t fields =
      query.fields & (ChunkQuery::kFeatures | ChunkQuery::kStats | ChunkQuery::kFree |
                      ChunkQuery::kIndex | ChunkQuery::kMoments);
  if (!(fields & ChunkQuery::kFeatures)) fields &= ~ChunkQuery::kMoments;  // they go with features
  const std::size_t limit =
      query.limit > 0 ? static_cast<std::size_t>(query.limit) : static_cast<std::size_t>(-1);
  ChunkVoxels out;
  out.fields = fields;
  if (fields & ChunkQuery::kStats) out.class_prob.resize(kNumClasses);

  const HeldBlocks held(query, m.epoch, m.grid, m.config.occupancy_threshold);
  if (held.active()) out.delta_of_version = held.version();
  const OccupiedTest occupied_at(query.occupancy_threshold);
  std::size_t occupied = 0;
  std::vector<Chosen> chosen;
  std::int32_t moment_rows = 0;
  for (const BlockKey& key : m.grid.blocksIn(region.box.blockLo(), region.box.blockHi())) {
    const Block& block = *m.grid.find(key);
    if (held.held(key, block)) continue;
    const bool inside = region.containsBlock(key, m.grid);
    const std::size_t block_start = occupied;
    for (int local = 0; local < kBlockVoxels; ++local) {
      if (!block.observed[local]) continue;
      // Most observed voxels are free space, which only kFree asks for: tested first.
      const float l = block.log_odds[local];
      const bool is_occupied = occupied_at(l);
      if (!is_occupied && !(fields & ChunkQuery::kFree)) continue;
      const VoxelIndex v = voxelOf(key, local);
      if (!inside && !region.covers(v)) continue;
      const Eigen::Vector3d c = m.grid.centre(v);
      if (!inside && !region.contains(c)) continue;
      if (is_occupied) {
        if (occupied == limit) {
          out.truncated = true;
          continue;
        }
        ++occupied;
        const VoxelStats* stats = block.statsOf(local);
        const bool moment_row = (fields & ChunkQuery::kFeatures) &&
                                (fields & ChunkQuery::kMoments) &&
                                (stats == nullptr || stats->count < chunk::kMomentsBelow);
        chosen.push_back({v, c, l, stats, moment_row ? moment_rows++ : -1});
      } else {
        if (out.free_index[0].size() == limit) {
          out.truncated = true;
          continue;
        }
        push3(out.free_index, v.x(), v.y(), v.z());
      }
    }
    const auto in_block = static_cast<std::int32_t>(occupied - block_start);
    if (in_block > 0 || (held.active() && held.changed(block))) {
      push3(out.block_key, key.x(), key.y(), key.z());
      out.block_voxels.push_back(in_block);
    }
  }
  sizeColumns(out, chosen.size(), static_cast<std::size_t>(moment_rows), fields);
  m.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chosen.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i)
                          writeOccupied(out, i, chosen[i], fields);
                      });
  });
  out.num_occupied = static_cast<std::int32_t>(occupied);
  if (out.count.empty()) out.class_prob.clear();  // class rows only with statistics
  return out;
}

}  // namespace socc::map
