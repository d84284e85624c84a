// SemanticOccupancyMap::queryChunk: voxels of a box or sphere in the column layout of
// chunk_reply_t. Blocks are visited in lexicographic key order and voxels in local order, so
// answers are deterministic (identical after a snapshot round trip).
#include <cmath>
#include <stdexcept>

#include "map_impl.hpp"
#include "region.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/map/voxel_features.hpp"

namespace socc::map {
namespace {

std::uint8_t toByte(double p) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(p, 0.0, 1.0) * 255.0));
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

void appendOccupied(chunk_reply_t& out, const VoxelIndex& v, const Eigen::Vector3d& centre,
                    float log_odds, const VoxelStats* stats, std::int32_t fields) {
  if (fields & chunk_request_t::FIELD_INDEX) out.index.push_back({v.x(), v.y(), v.z()});
  const VoxelStats empty;
  const VoxelStats& s = stats != nullptr ? *stats : empty;
  if (fields & chunk_request_t::FIELD_FEATURES) {
    if (stats != nullptr)
      out.first_point.push_back({s.first_point[0], s.first_point[1], s.first_point[2]});
    else  // occupied without statistics (only below the map's threshold): use the centre
      out.first_point.push_back({static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                                 static_cast<float>(centre.z())});
    const VoxelFeatures f = computeFeatures(s);
    const auto q = [](double c) { return static_cast<std::int16_t>(std::lround(c * 32767.0)); };
    out.normal.push_back({q(f.normal.x()), q(f.normal.y()), q(f.normal.z())});
    out.planarity.push_back(static_cast<float>(f.planarity));
    out.occupancy.push_back(toByte(probability(log_odds)));
    out.label.push_back(s.label);
    out.label_prob.push_back(s.has_semantics ? toByte(s.prob(s.label)) : 0);
  }
  if (fields & chunk_request_t::FIELD_STATS) {
    if (stats != nullptr)
      out.mean.push_back({s.mean[0], s.mean[1], s.mean[2]});
    else
      out.mean.push_back({static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                          static_cast<float>(centre.z())});
    const Eigen::Matrix3d c = s.covariance();
    out.covariance.push_back({static_cast<float>(c(0, 0)), static_cast<float>(c(0, 1)),
                              static_cast<float>(c(0, 2)), static_cast<float>(c(1, 1)),
                              static_cast<float>(c(1, 2)), static_cast<float>(c(2, 2))});
    out.count.push_back(static_cast<std::int32_t>(s.count));
    out.log_odds.push_back(log_odds);
    std::vector<float> probs(kNumClasses);
    for (int k = 0; k < kNumClasses; ++k) probs[k] = s.prob(k);
    out.class_prob.push_back(std::move(probs));
  }
}

}  // namespace

void SemanticOccupancyMap::queryChunk(const ChunkQuery& query, chunk_reply_t& out) const {
  checkQuery(query);
  const Impl& m = *impl_;
  const double vs = m.config.voxel_size;
  const bool sphere = query.shape == ChunkQuery::Shape::kSphere;
  const Eigen::Vector3d rmin =
      sphere ? (query.center.array() - query.radius).matrix() : query.box_min;
  const Eigen::Vector3d rmax =
      sphere ? (query.center.array() + query.radius).matrix() : query.box_max;
  const IndexBox box = IndexBox::of(rmin, rmax, vs);
  const double r2 = query.radius * query.radius;
  const auto inside = [&](const Eigen::Vector3d& c) {
    if (sphere) return (c - query.center).squaredNorm() <= r2;
    return (c.array() >= query.box_min.array()).all() && (c.array() <= query.box_max.array()).all();
  };

  const std::int32_t fields =
      query.fields & (chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS |
                      chunk_request_t::FIELD_FREE | chunk_request_t::FIELD_INDEX);
  const std::size_t limit =
      query.limit > 0 ? static_cast<std::size_t>(query.limit) : static_cast<std::size_t>(-1);
  out.voxel_size = vs;
  out.map_version = m.version;
  out.fields = fields;
  out.truncated = false;
  out.index.clear();
  out.first_point.clear();
  out.normal.clear();
  out.planarity.clear();
  out.occupancy.clear();
  out.label.clear();
  out.label_prob.clear();
  out.mean.clear();
  out.covariance.clear();
  out.count.clear();
  out.log_odds.clear();
  out.class_prob.clear();
  out.free_index.clear();

  std::size_t occupied = 0;
  for (const BlockKey& key : m.grid.blocksIn(box.blockLo(), box.blockHi())) {
    const Block& block = *m.grid.find(key);
    for (int local = 0; local < kBlockVoxels; ++local) {
      if (!block.observed[local]) continue;
      const VoxelIndex v = voxelOf(key, local);
      if ((v.array() < box.lo.array()).any() || (v.array() > box.hi.array()).any()) continue;
      const Eigen::Vector3d c = m.centre(v);
      if (!inside(c)) continue;
      const float l = block.log_odds[local];
      if (probability(l) >= query.occupancy_threshold) {
        if (occupied == limit) {
          out.truncated = true;
          continue;
        }
        ++occupied;
        appendOccupied(out, v, c, l, block.statsOf(local), fields);
      } else if (fields & chunk_request_t::FIELD_FREE) {
        if (out.free_index.size() == limit) {
          out.truncated = true;
          continue;
        }
        out.free_index.push_back({v.x(), v.y(), v.z()});
      }
    }
  }
  out.num_voxels = static_cast<std::int32_t>(occupied);
  out.n_index = static_cast<std::int32_t>(out.index.size());
  out.n_features = static_cast<std::int32_t>(out.occupancy.size());
  out.n_stats = static_cast<std::int32_t>(out.count.size());
  out.num_classes = out.n_stats > 0 ? kNumClasses : 0;
  out.n_free = static_cast<std::int32_t>(out.free_index.size());
}

}  // namespace socc::map
