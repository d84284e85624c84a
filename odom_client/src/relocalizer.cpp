#include "socc/odom/relocalizer.hpp"

#include <string>
#include <utility>

namespace socc::odom {
namespace {

PlaceRules rulesOf(const OdomConfig& c) {
  PlaceRules r;
  r.min_fitness = c.relocalize_min_fitness;
  r.margin = c.relocalize_margin;
  r.scan_lead = c.relocalize_scan_lead;
  r.confirm_scans = c.relocalize_confirm_scans;
  r.keep = static_cast<std::size_t>(c.relocalize_candidates);
  return r;
}

// The candidates not already followed (their verification would repeat a followed place's).
std::vector<Eigen::Isometry3d> withNew(std::vector<Eigen::Isometry3d> followed,
                                       const std::vector<Eigen::Isometry3d>& candidates) {
  const std::size_t known = followed.size();
  for (const Eigen::Isometry3d& c : candidates) {
    bool seen = false;
    for (std::size_t i = 0; i < known && !seen; ++i) seen = samePlace(followed[i], c);
    if (!seen) followed.push_back(c);
  }
  return followed;
}

}  // namespace

Relocalizer::Relocalizer(const OdomConfig& config)
    : config_(config),
      stack_(config, static_cast<std::size_t>(config.relocalize_stack_scans)),
      places_(rulesOf(config)) {}

Relocalization Relocalizer::add(const PreparedScan& scan, MapAccess& map,
                                const std::optional<PoseHint>& hint) {
  Relocalization out;
  stack_.add(scan);
  if (stack_.restarted()) places_.clear();  // the motions no longer connect the scans
  out.stacked = static_cast<int>(stack_.size());
  if (stack_.size() == 0) {
    out.problem = "waiting for the next scan (the first one's motion is not known yet)";
    return out;
  }
  return addStacked(stack_.cloud(), out.stacked, stack_.lastMotion(), map, hint);
}

Relocalization Relocalizer::addStacked(const PreparedScan& stacked, int scans,
                                       const Eigen::Isometry3d& motion, MapAccess& map,
                                       const std::optional<PoseHint>& hint) {
  const std::vector<Eigen::Vector3f> points =
      localizationPoints(stacked.cloud, config_.relocalize_voxel_size, kMaxLocalizePoints);
  std::vector<Eigen::Isometry3d> candidates;
  std::vector<Eigen::Isometry3d> poses;
  std::string problem;
  std::vector<VerifiedPlace> verified;
  try {
    candidates = map.candidates(points, hint, config_.relocalize_candidates);
    poses = withNew(places_.predicted(motion), candidates);
    if (!poses.empty()) verified = verifyPlaces(config_, stacked, points, map, poses, problem);
  } catch (const MapBusy& busy) {
    // The followed places missed this search's motion: confirmation starts again.
    return noPlace(scans, std::string("the map service could not search now: ") + busy.what());
  }
  if (poses.empty()) return noPlace(scans, "no candidate pose: the scans match nothing in the map");
  Relocalization verdict = places_.update(motion, std::move(verified));
  verdict.candidates = static_cast<int>(candidates.size());
  verdict.stacked = scans;
  if (!problem.empty() && !verdict.pose) verdict.problem = problem;
  return verdict;
}

Relocalization Relocalizer::noPlace(int scans, std::string problem) {
  places_.clear();
  Relocalization out;
  out.stacked = scans;
  out.problem = std::move(problem);
  return out;
}

}  // namespace socc::odom
