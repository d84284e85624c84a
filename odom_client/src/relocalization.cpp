#include "socc/odom/relocalization.hpp"

#include <algorithm>
#include <sstream>

#include "socc/odom/voxel_downsampling.hpp"

namespace socc::odom {
namespace {

// Verified poses closer than this are one place (ICP from two candidates converged together).
constexpr double kSameTranslation = 1.0;  // [m]
constexpr double kSameRotation = 0.09;    // [rad], about 5 deg

// Healthy refinements of poses, one per place (the better fitness), best fitness first.
std::vector<VerifiedPlace> refinedPlaces(const OdomConfig& config, const PreparedScan& scan,
                                         MapAccess& map,
                                         const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<VerifiedPlace> places;
  for (const Eigen::Isometry3d& candidate : poses) {
    Odometry probe(config, candidate);
    const LocalMap chunk = map.chunk(candidate.translation());
    const FrameEstimate e = probe.registerAt(scan, chunk, candidate);
    if (!e.registered || !e.health.healthy()) continue;
    VerifiedPlace place{e.pose, e.fitness};
    place.map_epoch = chunk.epoch();
    const auto same = [&](const VerifiedPlace& v) { return samePlace(v.pose, e.pose); };
    const auto it = std::find_if(places.begin(), places.end(), same);
    if (it == places.end())
      places.push_back(place);
    else if (e.fitness > it->fitness)
      *it = place;
  }
  std::sort(places.begin(), places.end(),
            [](const VerifiedPlace& a, const VerifiedPlace& b) { return a.fitness > b.fitness; });
  return places;
}

}  // namespace

bool samePlace(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() < kSameTranslation &&
         Eigen::AngleAxisd(d.linear()).angle() < kSameRotation;
}

std::string percentText(double share) {
  std::ostringstream out;
  out.precision(0);
  out << std::fixed << share * 100.0 << " %";
  return out.str();
}

const char* refusalName(Refusal refusal) {
  switch (refusal) {
    case Refusal::kNoCandidate:
      return "no_candidate";
    case Refusal::kNoRegistration:
      return "no_registration";
    case Refusal::kFreeSpace:
      return "free_space";
    case Refusal::kLowFitness:
      return "low_fitness";
    case Refusal::kAmbiguous:
      return "ambiguous";
    case Refusal::kNone:
      break;
  }
  return "none";
}

std::vector<VerifiedPlace> verifyPlaces(const OdomConfig& config, const PreparedScan& scan,
                                        const std::vector<Eigen::Vector3f>& points, MapAccess& map,
                                        const std::vector<Eigen::Isometry3d>& poses,
                                        std::string& problem, Refusal* refusal) {
  const auto refuse = [refusal](Refusal why) {
    if (refusal) *refusal = why;
  };
  std::vector<VerifiedPlace> places = refinedPlaces(config, scan, map, poses);
  if (places.empty()) {
    problem = "no candidate survived registration";
    refuse(Refusal::kNoRegistration);
    return places;
  }
  std::vector<Eigen::Isometry3d> refined;
  for (const VerifiedPlace& v : places) refined.push_back(v.pose);
  const std::vector<SpaceCheck> checks = map.check(points, refined);
  std::vector<VerifiedPlace> consistent;
  for (std::size_t i = 0; i < places.size() && i < checks.size(); ++i) {
    places[i].free = checks[i].free;
    if (checks[i].free <= config.relocalize_max_free)
      consistent.push_back(places[i]);
    else if (consistent.empty() && problem.empty())
      problem = "the best place puts " + percentText(checks[i].free) +
                " of the scan into space the map saw free (> " +
                percentText(config.relocalize_max_free) + ")";
  }
  if (!consistent.empty()) problem.clear();
  refuse(consistent.empty() ? Refusal::kFreeSpace : Refusal::kNone);
  std::sort(
      consistent.begin(), consistent.end(),
      [](const VerifiedPlace& a, const VerifiedPlace& b) { return a.evidence() > b.evidence(); });
  return consistent;
}

std::vector<Eigen::Vector3f> localizationPoints(const LabeledCloud& cloud, double voxel_size,
                                                std::size_t max_points) {
  const std::array<double, kNumClasses> same_size = [] {
    std::array<double, kNumClasses> a{};
    a.fill(1.0);
    return a;
  }();
  LabeledCloud geometry;
  geometry.points = cloud.points;  // labels play no part in the server's search
  LabeledCloud down = semanticVoxelDownsample(geometry, voxel_size, same_size);
  while (down.size() > std::min(max_points, kMaxLocalizePoints)) {
    voxel_size *= 1.5;
    down = semanticVoxelDownsample(geometry, voxel_size, same_size);
  }
  return down.points;
}

Relocalization relocalize(const OdomConfig& config, const PreparedScan& scan, MapAccess& map,
                          const std::optional<PoseHint>& hint) {
  Relocalization out;
  const std::vector<Eigen::Vector3f> points =
      localizationPoints(scan.cloud, config.relocalize_voxel_size, kMaxLocalizePoints);
  const std::vector<Eigen::Isometry3d> candidates =
      map.candidates(points, hint, config.relocalize_candidates);
  out.candidates = static_cast<int>(candidates.size());
  if (candidates.empty()) {
    out.problem = "no candidate pose: the scan matches nothing in the map";
    out.refusal = Refusal::kNoCandidate;
    return out;
  }
  const std::vector<VerifiedPlace> places =
      verifyPlaces(config, scan, points, map, candidates, out.problem, &out.refusal);
  if (places.empty()) return out;
  out.fitness = places[0].fitness;
  out.free = places[0].free;
  out.evidence = places[0].evidence();
  out.runner_up = places.size() > 1 ? places[1].evidence() : 0.0;
  if (out.fitness < config.relocalize_min_fitness) {
    out.problem = "best candidate explains " + percentText(out.fitness) + " of the scan (< " +
                  percentText(config.relocalize_min_fitness) + ")";
    out.refusal = Refusal::kLowFitness;
  } else if (out.evidence - out.runner_up < config.relocalize_margin) {
    out.problem = "ambiguous: two places explain " + percentText(out.evidence) + " and " +
                  percentText(out.runner_up) + " of the scan net of the free space they contradict";
    out.refusal = Refusal::kAmbiguous;
  } else {
    out.pose = places[0].pose;
  }
  out.map_epoch = places[0].map_epoch;
  return out;
}

}  // namespace socc::odom
