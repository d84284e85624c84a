#pragma once
// A robot's search for its pose in the shared map, scan after scan (odom_client --relocalize,
// recovery after LOST; docs/relocalization.md). Each scan is registered by the robot's own
// odometry onto the few before it (ScanStack: a private frame, nothing is written to the map);
// the stacked scans go to the server's search as one cloud; its candidates and the places
// followed from earlier scans (moved by the odometry) are verified against the map
// (verifyPlaces); a place is accepted once it has led by the margin on relocalize_confirm_scans
// consecutive scans (PlaceTracker).
#include <optional>
#include <string>

#include "socc/odom/place_tracker.hpp"
#include "socc/odom/relocalization.hpp"
#include "socc/odom/scan_stack.hpp"

namespace socc::odom {

class Relocalizer {
 public:
  explicit Relocalizer(const OdomConfig& config);

  /// One scan of the search. pose, when set: map_T_sensor of this scan at its reference time.
  Relocalization add(const PreparedScan& scan, MapAccess& map, const std::optional<PoseHint>& hint);

  /// One search of a robot whose own odometry stacked its scans already (OwnFrameMap): stacked
  /// is that cloud in its newest scan's frame, motion the robot's motion since the previous
  /// search (previous_T_newest), which moves the followed places. Same search, verification and
  /// confirmation as add(); pose, when set: map_T_sensor of the newest stacked scan.
  Relocalization addStacked(const PreparedScan& stacked, int scans, const Eigen::Isometry3d& motion,
                            MapAccess& map, const std::optional<PoseHint>& hint);

 private:
  /// A search that follows no place any more (problem: why).
  Relocalization noPlace(int scans, std::string problem);

  OdomConfig config_;
  ScanStack stack_;
  PlaceTracker places_;
};

}  // namespace socc::odom
