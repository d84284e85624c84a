#include "global_localizer.hpp"

#include <algorithm>
#include <cmath>

#include "socc/map/semantic_voxel.hpp"

namespace socc::localization {
namespace {

// A surface seen from a sensor has free space on the sensor's side: the map's normals are
// turned towards the side its rays cleared, as a scan's are turned towards its sensor.
constexpr double kFreeProbe = 1.0;  // [m] how far from the surface the free side is probed

bool freeAt(const map::SemanticOccupancyMap& map, const Eigen::Vector3f& p) {
  const double occupancy = map.occupancyAt(p.cast<double>());
  return occupancy >= 0.0 && occupancy < map.config().occupancy_threshold;
}

NormalSideTest freeSideOf(const map::SemanticOccupancyMap& map) {
  return [&map](const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
    const Eigen::Vector3f step = n * static_cast<float>(kFreeProbe);
    return !freeAt(map, p + step) && freeAt(map, p - step);
  };
}

std::vector<Eigen::Vector3f> occupiedPoints(const map::SemanticOccupancyMap& map) {
  map::ChunkQuery query;
  query.shape = map::ChunkQuery::Shape::kBox;
  query.box_min.setConstant(-map.config().max_abs_coordinate);
  query.box_max.setConstant(map.config().max_abs_coordinate);
  query.occupancy_threshold = map.config().occupancy_threshold;
  query.fields = map::ChunkQuery::kFeatures;
  const map::ChunkVoxels voxels = map.queryChunk(query);
  std::vector<Eigen::Vector3f> points(static_cast<std::size_t>(voxels.num_occupied));
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = {voxels.first_point[0][i], voxels.first_point[1][i], voxels.first_point[2][i]};
  return points;
}

bool withinHint(const Eigen::Isometry3d& pose, const std::optional<LocalizeHint>& hint) {
  if (!hint) return true;
  if ((pose.translation() - hint->position).norm() > hint->radius) return false;
  if (hint->yaw_tolerance >= M_PI) return true;
  const double d = std::remainder(yawOf(pose) - hint->yaw, 2.0 * M_PI);
  return std::abs(d) <= hint->yaw_tolerance;
}

// Every k-th point: a spread of the scan on which the search checks free space cheaply.
std::vector<Eigen::Vector3f> spread(const std::vector<Eigen::Vector3f>& scan, int count) {
  if (count <= 0 || scan.size() <= static_cast<std::size_t>(count)) return scan;
  std::vector<Eigen::Vector3f> out;
  const double step = static_cast<double>(scan.size()) / count;
  for (int i = 0; i < count; ++i) out.push_back(scan[static_cast<std::size_t>(i * step)]);
  return out;
}

// Free-space evidence at p that a pose error of up to margin cannot explain: p and (margin > 0)
// the six points margin away along the axes all lie in space the map saw free; the weakest
// evidence of them (0 when any is occupied or unobserved). A voxel at the lower clamp (missed by
// many rays) counts fully, one missed by a single ray (a map of one scan) or flickering at a
// surface hardly at all.
double freeEvidence(const map::SemanticOccupancyMap& map, const Eigen::Vector3d& p, double margin,
                    double confident) {
  double weakest = 1.0;
  const int probes = margin > 0.0 ? 7 : 1;
  for (int k = 0; k < probes; ++k) {
    Eigen::Vector3d q = p;
    if (k > 0) q[(k - 1) / 2] += (k % 2 ? margin : -margin);
    const double occupancy = map.occupancyAt(q);
    if (occupancy < 0.0 || occupancy >= map.config().occupancy_threshold) return 0.0;
    weakest = std::min(weakest, -map::logit(occupancy) / confident);
  }
  return std::min(1.0, weakest);
}

// The scan points a pose puts into observed space, and their summed free-space evidence.
struct FreeTally {
  std::size_t observed = 0;
  double free = 0.0;
};
FreeTally tallyFree(const map::SemanticOccupancyMap& map, const std::vector<Eigen::Vector3f>& scan,
                    const Eigen::Isometry3d& pose, double margin) {
  const double confident = std::abs(map::logit(map.config().clamp_min));
  FreeTally t;
  for (const Eigen::Vector3f& point : scan) {
    const Eigen::Vector3d p = pose * point.cast<double>();
    if (map.occupancyAt(p) < 0.0) continue;
    ++t.observed;
    t.free += freeEvidence(map, p, margin, confident);
  }
  return t;
}

// The share of the observed scan points a pose puts into free space deeper than margin: the
// search's poses are good to about a keypoint spacing, and a point that close to a surface
// proves nothing against them.
double conflictOf(const map::SemanticOccupancyMap& map, const std::vector<Eigen::Vector3f>& scan,
                  const Eigen::Isometry3d& pose, double margin) {
  const FreeTally t = tallyFree(map, scan, pose, margin);
  return t.observed == 0 ? 0.0 : t.free / static_cast<double>(t.observed);
}

}  // namespace

SpaceCheck checkFreeSpace(const map::SemanticOccupancyMap& map,
                          const std::vector<Eigen::Vector3f>& scan, const Eigen::Isometry3d& pose) {
  const FreeTally t = tallyFree(map, scan, pose, 0.0);  // exact poses: no margin
  SpaceCheck out;
  if (scan.empty() || t.observed == 0) return out;
  out.observed = static_cast<double>(t.observed) / static_cast<double>(scan.size());
  out.free = t.free / static_cast<double>(t.observed);
  return out;
}

double yawOf(const Eigen::Isometry3d& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

struct GlobalLocalizer::Impl {
  explicit Impl(const LocalizerParams& p) : params(p) {}

  LocalizerParams params;
  std::shared_ptr<MapFeatures> map;  // described by the first search after a rebuild
  std::int64_t map_occupied = -1;    // occupied voxels when map was built; -1: never

  void refresh(const map::SemanticOccupancyMap& m) {
    const std::int64_t occupied = m.stats().num_occupied;
    const double change = std::abs(static_cast<double>(occupied - map_occupied));
    if (map && change <= params.rebuild_change * static_cast<double>(map_occupied)) return;
    map = std::make_shared<MapFeatures>(
        orientedKeypoints(occupiedPoints(m), params.features, freeSideOf(m)), params.features);
    map_occupied = occupied;
  }
};

GlobalLocalizer::GlobalLocalizer(LocalizerParams params) : impl_(std::make_unique<Impl>(params)) {}
GlobalLocalizer::~GlobalLocalizer() = default;
GlobalLocalizer::GlobalLocalizer(GlobalLocalizer&&) noexcept = default;
GlobalLocalizer& GlobalLocalizer::operator=(GlobalLocalizer&&) noexcept = default;

std::size_t GlobalLocalizer::mapKeypoints() const {
  return impl_->map ? impl_->map->get().cloud.size() : 0;
}

LocalizeSearch GlobalLocalizer::prepare(const map::SemanticOccupancyMap& map,
                                        std::vector<Eigen::Vector3f> scan,
                                        const std::optional<LocalizeHint>& hint,
                                        int max_candidates) {
  impl_->refresh(map);
  LocalizeSearch search;
  search.params_ = impl_->params;
  search.map_ = impl_->map;
  search.scan_ = std::move(scan);
  search.hint_ = hint;
  search.max_candidates_ = max_candidates;
  return search;
}

LocalizeAnswer GlobalLocalizer::finish(const map::SemanticOccupancyMap& map,
                                       LocalizeSearch search) {
  LocalizeAnswer answer = std::move(search.answer_);
  if (search.found_.empty()) return answer;
  const std::vector<Eigen::Vector3f> checked = spread(search.scan_, search.params_.conflict_points);
  const double margin = search.params_.search.inlier_distance;
  const ConflictAt conflict = [&map, &checked, margin](const Eigen::Isometry3d& pose) {
    return conflictOf(map, checked, pose, margin);
  };
  for (const Hypothesis& h :
       rankHypotheses(std::move(search.found_), conflict, search.params_.search))
    if (withinHint(h.pose, search.hint_) &&
        static_cast<int>(answer.candidates.size()) < search.max_candidates_)
      answer.candidates.push_back({h.pose, h.inliers, h.inlier_fraction, h.conflict, h.score});
  return answer;
}

LocalizeAnswer GlobalLocalizer::localize(const map::SemanticOccupancyMap& map,
                                         const std::vector<Eigen::Vector3f>& scan,
                                         const std::optional<LocalizeHint>& hint,
                                         int max_candidates) {
  LocalizeSearch search = prepare(map, scan, hint, max_candidates);
  search.run();
  return finish(map, std::move(search));
}

}  // namespace socc::localization
