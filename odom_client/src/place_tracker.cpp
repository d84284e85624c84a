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
    Place followed{v, 0, 0.0};  // its lead before this scan, where the odometry takes one
    for (const Place& p : places_)
      if (samePlace(p.verified.pose * motion, v.pose) && p.lead > followed.lead) {
        followed.lead = p.lead;
        followed.summed = p.summed;
      }
    next.push_back(followed);
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
  const double gap = out.evidence - out.runner_up;
  const bool leads = out.evidence >= rules_.min_fitness && gap >= rules_.scan_lead - 1e-9;
  for (std::size_t i = 1; i < next.size(); ++i) next[i] = {next[i].verified, 0, 0.0};
  best.lead = leads ? best.lead + 1 : 0;
  best.summed = leads ? best.summed + gap : 0.0;
  out.confirmed = best.lead;
  out.lead = best.summed;
  // Leads add up over the confirming scans: a place 9 points ahead on each of three scans is
  // taken as one 10 points ahead on two is. Consecutive stacks share scans, so the sum is not of
  // independent tests; the floor (scan_lead) on every scan keeps a faint one from adding up (a
  // quarter-turn lookalike 5 points ahead of a room whose furniture moved did, at 0.05).
  const double needed = rules_.margin * rules_.confirm_scans;
  if (out.evidence < rules_.min_fitness)
    out.problem = "best place explains " + percentText(out.evidence) +
                  " of the scans net of the free space it contradicts (< " +
                  percentText(rules_.min_fitness) + ")";
  else if (!leads)
    out.problem = "ambiguous: two places explain " + percentText(out.evidence) + " and " +
                  percentText(out.runner_up) +
                  " of the scans net of the free space they contradict";
  else if (best.lead < rules_.confirm_scans || best.summed < needed - 1e-9)
    out.problem = "confirming: the best place led on " + std::to_string(best.lead) +
                  " consecutive scans by " + percentText(best.summed) +
                  " of the scans in all (needs " + std::to_string(rules_.confirm_scans) +
                  " scans and " + percentText(needed) + ")";
  else
    out.pose = best.verified.pose;
  out.map_epoch = best.verified.map_epoch;
  if (next.size() > rules_.keep) next.resize(rules_.keep);
  places_ = std::move(next);
  return out;
}

}  // namespace socc::odom
