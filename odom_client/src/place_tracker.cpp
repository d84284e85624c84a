#include "socc/odom/place_tracker.hpp"

#include <algorithm>

namespace socc::odom {

std::vector<Eigen::Isometry3d> PlaceTracker::predicted(const Eigen::Isometry3d& motion) const {
  std::vector<Eigen::Isometry3d> out;
  for (const Place& p : places_) out.push_back(p.verified.pose * motion);
  return out;
}

Relocalization PlaceTracker::update(const Eigen::Isometry3d& motion,
                                    std::vector<VerifiedPlace> verified) {
  std::sort(verified.begin(), verified.end(), [](const VerifiedPlace& a, const VerifiedPlace& b) {
    return a.evidence() > b.evidence();
  });
  std::vector<Place> next;
  for (const VerifiedPlace& v : verified) {
    // One place per location: the better evidence (first) stands for it.
    const auto same = [&v](const Place& p) { return samePlace(p.verified.pose, v.pose); };
    if (std::any_of(next.begin(), next.end(), same)) continue;
    int lead = 0;  // its lead before this scan
    for (const Place& p : places_)
      if (samePlace(p.verified.pose * motion, v.pose)) lead = std::max(lead, p.lead);
    next.push_back({v, lead});
  }
  Relocalization out;
  if (next.empty()) {
    places_.clear();
    out.problem = "no place verified";
    return out;
  }
  Place& best = next.front();
  out.fitness = best.verified.fitness;
  out.free = best.verified.free;
  out.evidence = best.verified.evidence();
  out.runner_up = next.size() > 1 ? next[1].verified.evidence() : 0.0;
  // The share explained must stand net of the points the place contradicts: a lookalike that
  // explains 64 % of the scans but puts 20 % of them into free space explains 44 %.
  const bool leads =
      out.evidence >= rules_.min_fitness && out.evidence - out.runner_up >= rules_.margin;
  for (std::size_t i = 1; i < next.size(); ++i) next[i].lead = 0;
  best.lead = leads ? best.lead + 1 : 0;
  out.confirmed = best.lead;
  if (out.evidence < rules_.min_fitness)
    out.problem = "best place explains " + percentText(out.evidence) +
                  " of the scans net of the free space it contradicts (< " +
                  percentText(rules_.min_fitness) + ")";
  else if (!leads)
    out.problem = "ambiguous: two places explain " + percentText(out.evidence) + " and " +
                  percentText(out.runner_up) +
                  " of the scans net of the free space they contradict";
  else if (best.lead < rules_.confirm_scans)
    out.problem = "confirming: the best place led on " + std::to_string(best.lead) + " of " +
                  std::to_string(rules_.confirm_scans) + " consecutive scans";
  else
    out.pose = best.verified.pose;
  if (next.size() > rules_.keep) next.resize(rules_.keep);
  places_ = std::move(next);
  return out;
}

}  // namespace socc::odom
