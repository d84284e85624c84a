#pragma once
// The places a searching robot might be at, followed from scan to scan by its odometry, and the
// rule that accepts one (docs/relocalization.md "Confirmation"). A place leads on a scan when it
// is verified against the map, explains at least min_fitness of the stacked scans net of the share
// it puts into free space, and is ahead of every other place still verified by at least scan_lead.
// It is accepted once it led on at least confirm_scans consecutive scans and its leads
// over them add up to confirm_scans * margin (a sequential test: a small lead seen again and
// again is as much evidence as a large one seen twice). Places once found stay rivals as long as
// they keep verifying (moved by odometry, not searched again), so a lookalike cannot win on a scan
// whose search happened to miss the true place, and a place whose lead rests on one scan's luck is
// not taken.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "socc/odom/relocalization.hpp"

namespace socc::odom {

struct PlaceRules {
  double min_fitness = 0.5;  // relocalize_min_fitness
  double margin = 0.1;       // relocalize_margin, on evidence (fitness - free), per scan on average
  double scan_lead = 0.08;   // relocalize_scan_lead: on each scan at least (margin: every scan)
  int confirm_scans = 2;     // relocalize_confirm_scans
  std::size_t keep = 5;      // places followed at most (best evidence first)
};

class PlaceTracker {
 public:
  explicit PlaceTracker(PlaceRules rules) : rules_(rules) {}

  /// The followed places moved by the robot's motion since the last scan (previous_T_newest):
  /// where to verify them on the new scan.
  std::vector<Eigen::Isometry3d> predicted(const Eigen::Isometry3d& motion) const;

  /// The places verified on the new scan (verifyPlaces: consistent ones, any order; predicted
  /// ones among them keep their history through samePlace with their prediction). Returns the
  /// verdict on the leader: pose set when it is confirmed; otherwise the problem says why not.
  Relocalization update(const Eigen::Isometry3d& motion, std::vector<VerifiedPlace> verified);

  /// Forgets every place (the robot's odometry restarted: motions no longer connect the scans).
  void clear() { places_.clear(); }
  std::size_t size() const { return places_.size(); }

 private:
  struct Place {
    VerifiedPlace verified;
    int lead = 0;         // consecutive scans it led by at least scan_lead, this one included
    double summed = 0.0;  // its evidence above the runner-up's, summed over those scans
  };
  std::vector<Place> places_;
  PlaceRules rules_;
};

}  // namespace socc::odom
