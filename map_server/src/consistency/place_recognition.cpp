#include "place_recognition.hpp"

#include <algorithm>
#include <cmath>

#include "socc/odom/odometry.hpp"
#include "submap_access.hpp"

namespace socc::consistency {
namespace {

// Along-track shifts of each guess also registered: on a street of repeated facades a guess
// that converges to a lookalike then meets the true place among the verified poses, and the
// relocalization's margin refuses the ambiguous closure instead of accepting the lookalike.
constexpr double kProbeShift = 4.0;  // [m]

bool eligible(const Keyframe& query, const Keyframe& other, const ConsistencyParams& params) {
  if (other.id == query.id || other.points.empty()) return false;  // empty: kept as a pose only
  if (other.robot != query.robot) return true;
  return query.travelled - other.travelled >= params.min_loop_travel;
}

double searchRadius(const Keyframe& query, const Keyframe& other, const ConsistencyParams& p) {
  const double apart = other.robot == query.robot ? query.travelled - other.travelled
                                                  : query.travelled + other.travelled;
  return std::min(p.max_search_radius, p.search_radius + p.drift_share * std::abs(apart));
}

Eigen::Isometry3d yawOnly(double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

// The nearest eligible keyframe within its search radius of the query's estimate.
std::optional<Candidate> nearest(const std::vector<Keyframe>& keyframes, int query,
                                 const std::vector<Eigen::Isometry3d>& estimates,
                                 const ConsistencyParams& params) {
  const Keyframe& q = keyframes[static_cast<std::size_t>(query)];
  const Eigen::Vector3d at = estimates[static_cast<std::size_t>(query)].translation();
  std::optional<Candidate> best;
  double best_distance = 0.0;
  for (const Keyframe& k : keyframes) {
    if (!eligible(q, k, params)) continue;
    const Eigen::Isometry3d& e = estimates[static_cast<std::size_t>(k.id)];
    const double d = (e.translation() - at).norm();
    if (d > searchRadius(q, k, params) || (best && d >= best_distance)) continue;
    best = Candidate{k.id, e.inverse() * estimates[static_cast<std::size_t>(query)], false};
    best_distance = d;
  }
  return best;
}

// The eligible keyframes whose descriptor matches best (ring keys first, then in full).
std::vector<Candidate> byDescriptor(const std::vector<Keyframe>& keyframes, int query,
                                    const ConsistencyParams& params) {
  const Keyframe& q = keyframes[static_cast<std::size_t>(query)];
  std::vector<std::pair<float, int>> ranked;
  for (const Keyframe& k : keyframes)
    if (eligible(q, k, params) && !k.descriptor.empty())
      ranked.emplace_back((k.descriptor.ringKey() - q.descriptor.ringKey()).squaredNorm(), k.id);
  const std::size_t keep = std::min<std::size_t>(ranked.size(), 10);
  std::partial_sort(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(keep),
                    ranked.end());
  std::vector<std::pair<double, Candidate>> matched;
  for (std::size_t i = 0; i < keep; ++i) {
    const Keyframe& k = keyframes[static_cast<std::size_t>(ranked[i].second)];
    const ScanContext::Match m = q.descriptor.compare(k.descriptor);
    if (m.distance <= params.max_descriptor_distance)
      matched.push_back({m.distance, Candidate{k.id, yawOnly(m.yaw), true}});
  }
  std::sort(matched.begin(), matched.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Candidate> out;
  for (const auto& [distance, c] : matched) {
    if (static_cast<int>(out.size()) >= params.descriptor_candidates) break;
    out.push_back(c);
  }
  return out;
}

std::vector<SubmapScan> submapOf(const std::vector<Keyframe>& keyframes, int center,
                                 const std::vector<Eigen::Isometry3d>& estimates, int neighbours) {
  const Keyframe& c = keyframes[static_cast<std::size_t>(center)];
  const Eigen::Isometry3d frame = estimates[static_cast<std::size_t>(center)].inverse();
  std::vector<SubmapScan> scans;
  for (const Keyframe& k : keyframes)
    if (k.robot == c.robot && std::abs(k.robot_kf - c.robot_kf) <= neighbours)
      scans.push_back({&k.points, frame * estimates[static_cast<std::size_t>(k.id)]});
  return scans;
}

std::vector<Eigen::Isometry3d> probes(const Eigen::Isometry3d& guess) {
  std::vector<Eigen::Isometry3d> out = {guess};
  for (const double shift : {kProbeShift, -kProbeShift})
    out.push_back(guess * Eigen::Translation3d(shift, 0.0, 0.0));
  return out;
}

}  // namespace

std::vector<Candidate> findCandidates(const std::vector<Keyframe>& keyframes, int query,
                                      const std::vector<Eigen::Isometry3d>& estimates,
                                      const ConsistencyParams& params) {
  std::vector<Candidate> out;
  if (const std::optional<Candidate> n = nearest(keyframes, query, estimates, params))
    out.push_back(*n);
  for (const Candidate& c : byDescriptor(keyframes, query, params)) {
    const auto same = [&c](const Candidate& o) { return o.keyframe == c.keyframe; };
    if (std::none_of(out.begin(), out.end(), same)) out.push_back(c);
  }
  return out;
}

std::optional<Closure> verifyCandidate(const std::vector<Keyframe>& keyframes, int query,
                                       const std::vector<Candidate>& candidates,
                                       const std::vector<Eigen::Isometry3d>& estimates,
                                       const ConsistencyParams& params,
                                       const map::MapConfig& map_config,
                                       const odom::OdomConfig& odom_config, std::string* problem,
                                       RefusalCounts* refused) {
  const Keyframe& q = keyframes[static_cast<std::size_t>(query)];
  LabeledCloud cloud;
  cloud.points = q.points;
  const odom::PreparedScan scan = odom::prepareScan(odom_config, cloud, q.seq, q.utime);
  for (const Candidate& c : candidates) {
    SubmapAccess submap(map_config,
                        submapOf(keyframes, c.keyframe, estimates, params.submap_neighbours),
                        probes(c.guess), params.chunk_radius);
    odom::OdomConfig config = odom_config;
    config.relocalize_candidates = 3;
    const odom::Relocalization r = odom::relocalize(config, scan, submap, std::nullopt);
    if (!r.pose) {
      if (problem) *problem = r.problem;
      if (refused) ++(*refused)[static_cast<std::size_t>(r.refusal)];
      continue;
    }
    Closure closure;
    closure.from = c.keyframe;
    closure.to = query;
    closure.relative = *r.pose;
    closure.fitness = r.fitness;
    closure.free = r.free;
    closure.by_descriptor = c.by_descriptor;
    return closure;
  }
  return std::nullopt;
}

}  // namespace socc::consistency
