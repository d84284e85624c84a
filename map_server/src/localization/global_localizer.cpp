#include "global_localizer.hpp"

#include <pcl/registration/sample_consensus_prerejective.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "socc/map/semantic_voxel.hpp"

namespace socc::localization {
namespace {

using Aligner =
    pcl::SampleConsensusPrerejective<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33>;

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

bool sameHypothesis(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                    const LocalizerParams& params) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() < params.distinct_translation &&
         Eigen::AngleAxisd(d.linear()).angle() < params.distinct_rotation;
}

bool withinHint(const Eigen::Isometry3d& pose, const std::optional<LocalizeHint>& hint) {
  if (!hint) return true;
  if ((pose.translation() - hint->position).norm() > hint->radius) return false;
  if (hint->yaw_tolerance >= M_PI) return true;
  const double d = std::remainder(yawOf(pose) - hint->yaw, 2.0 * M_PI);
  return std::abs(d) <= hint->yaw_tolerance;
}

// The map keypoints a scan seen from within the hint can overlap.
FeatureCloud nearHint(const FeatureCloud& map, const LocalizeHint& hint, double reach) {
  FeatureCloud out;
  for (std::size_t i = 0; i < map.size(); ++i) {
    const Eigen::Vector3d p = (*map.keypoints)[i].getVector3fMap().cast<double>();
    if ((p - hint.position).norm() > hint.radius + reach) continue;
    out.keypoints->push_back((*map.keypoints)[i]);
    out.features->push_back((*map.features)[i]);
  }
  return out;
}

double reachOf(const FeatureCloud& scan) {
  double reach = 0.0;
  for (const pcl::PointNormal& p : *scan.keypoints)
    reach = std::max(reach, static_cast<double>(p.getVector3fMap().norm()));
  return reach;
}

}  // namespace

SpaceCheck checkFreeSpace(const map::SemanticOccupancyMap& map,
                          const std::vector<Eigen::Vector3f>& scan, const Eigen::Isometry3d& pose) {
  // Free space is weighed by the evidence for it: a voxel at the lower clamp (missed by many
  // rays) counts fully, one missed by a single ray (a map of one scan) or flickering at a
  // surface hardly at all.
  const double confident = std::abs(map::logit(map.config().clamp_min));
  std::size_t observed = 0;
  double free = 0.0;
  for (const Eigen::Vector3f& p : scan) {
    const double occupancy = map.occupancyAt(pose * p.cast<double>());
    if (occupancy < 0.0) continue;
    ++observed;
    if (occupancy < map.config().occupancy_threshold)
      free += std::min(1.0, -map::logit(occupancy) / confident);
  }
  SpaceCheck out;
  if (scan.empty() || observed == 0) return out;
  out.observed = static_cast<double>(observed) / static_cast<double>(scan.size());
  out.free = free / static_cast<double>(observed);
  return out;
}

double yawOf(const Eigen::Isometry3d& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

struct GlobalLocalizer::Impl {
  explicit Impl(const LocalizerParams& p) : params(p) {}

  LocalizerParams params;
  FeatureCloud map;
  std::int64_t map_occupied = -1;  // occupied voxels when map was built; -1: never
  Aligner aligner;                 // target = map: its feature tree is built once per rebuild

  void configure(Aligner& a) const {
    a.setMaximumIterations(params.iterations);
    a.setNumberOfSamples(3);
    a.setCorrespondenceRandomness(params.correspondence_randomness);
    a.setSimilarityThreshold(static_cast<float>(params.similarity));
    a.setMaxCorrespondenceDistance(params.inlier_distance);
    a.setInlierFraction(static_cast<float>(params.min_inlier_fraction));
  }

  void refresh(const map::SemanticOccupancyMap& m) {
    const std::int64_t occupied = m.stats().num_occupied;
    const double change = std::abs(static_cast<double>(occupied - map_occupied));
    if (map_occupied >= 0 && change <= params.rebuild_change * static_cast<double>(map_occupied))
      return;
    map = describe(occupiedPoints(m), params.features, freeSideOf(m));
    map_occupied = occupied;
    aligner = Aligner();
    configure(aligner);
    if (map.size() == 0) return;
    aligner.setInputTarget(map.keypoints);
    aligner.setTargetFeatures(map.features);
  }

  // Distinct hypotheses of all runs, most inliers first.
  std::vector<PoseCandidate> search(Aligner& a, const FeatureCloud& scan) const {
    a.setInputSource(scan.keypoints);
    a.setSourceFeatures(scan.features);
    std::vector<PoseCandidate> found;
    pcl::PointCloud<pcl::PointNormal> aligned;
    // On a small or repetitive map most samples pass the pre-rejection and are scored, so the
    // cost of a run varies by orders of magnitude: runs go on until the time budget is spent.
    const auto start = std::chrono::steady_clock::now();
    const auto spent = [&start] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    for (int run = 0; run < params.runs && (run == 0 || spent() < params.max_seconds); ++run) {
      // PCL draws its samples with std::rand: seeded per run, answers are reproducible.
      std::srand(static_cast<unsigned>(run + 1));
      a.align(aligned);
      if (!a.hasConverged()) continue;
      PoseCandidate c;
      c.pose.matrix() = a.getFinalTransformation().cast<double>();
      c.inliers = static_cast<int>(a.getInliers().size());
      c.inlier_fraction = static_cast<double>(c.inliers) / static_cast<double>(scan.size());
      const auto same = [&](const PoseCandidate& o) {
        return sameHypothesis(o.pose, c.pose, params);
      };
      const auto it = std::find_if(found.begin(), found.end(), same);
      if (it == found.end())
        found.push_back(c);
      else if (c.inliers > it->inliers)
        *it = c;
    }
    std::sort(found.begin(), found.end(),
              [](const PoseCandidate& x, const PoseCandidate& y) { return x.inliers > y.inliers; });
    return found;
  }
};

GlobalLocalizer::GlobalLocalizer(LocalizerParams params) : impl_(std::make_unique<Impl>(params)) {}
GlobalLocalizer::~GlobalLocalizer() = default;
GlobalLocalizer::GlobalLocalizer(GlobalLocalizer&&) noexcept = default;
GlobalLocalizer& GlobalLocalizer::operator=(GlobalLocalizer&&) noexcept = default;

std::size_t GlobalLocalizer::mapKeypoints() const {
  return impl_->map.size();
}

LocalizeAnswer GlobalLocalizer::localize(const map::SemanticOccupancyMap& map,
                                         const std::vector<Eigen::Vector3f>& scan,
                                         const std::optional<LocalizeHint>& hint,
                                         int max_candidates) {
  impl_->refresh(map);
  LocalizeAnswer answer;
  answer.map_keypoints = impl_->map.size();
  const FeatureCloud source = describe(scan, impl_->params.features);
  answer.scan_keypoints = source.size();
  if (source.size() < 3 || impl_->map.size() < 3) return answer;

  std::vector<PoseCandidate> found;
  if (hint) {
    // Only the map a scan from within the hint can see: a smaller feature tree, fewer lookalikes.
    Aligner local;
    impl_->configure(local);
    const FeatureCloud target = nearHint(impl_->map, *hint, reachOf(source));
    if (target.size() < 3) return answer;
    local.setInputTarget(target.keypoints);
    local.setTargetFeatures(target.features);
    found = impl_->search(local, source);
  } else {
    found = impl_->search(impl_->aligner, source);
  }
  for (const PoseCandidate& c : found)
    if (withinHint(c.pose, hint) && static_cast<int>(answer.candidates.size()) < max_candidates)
      answer.candidates.push_back(c);
  return answer;
}

}  // namespace socc::localization
