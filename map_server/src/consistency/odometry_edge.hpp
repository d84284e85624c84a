#pragma once
// The pose graph's odometry edge between two consecutive keyframes of a robot, measured so that
// it does not see the shared map (docs/consistency.md, "Odometry edges that do not see the
// map"). The integrated relative pose of two keyframes is the robot's motion plus, at a revisit,
// its pull onto the old walls (the client registers against the shared map): taken as is, the
// graph sees a loop that closes and moves nothing. So each keyframe's scan is also registered
// against its predecessor's scan alone (the robot's own data, a one-keyframe submap, from the
// integrated relative pose). Where the two disagree beyond the registration's noise, the edge
// takes the scan-to-scan measurement: the revisit's closure then contradicts the chain and the
// optimizer spreads the loop's error over it. Otherwise, or when the registration fails, the
// integrated edge stays (a pure scan-to-scan chain drifts more than the client's odometry).
#include <Eigen/Geometry>
#include <optional>

#include "consistency_params.hpp"
#include "keyframe.hpp"
#include "pose_graph.hpp"
#include "socc/map/map_config.hpp"
#include "socc/odom/odom_config.hpp"

namespace socc::consistency {

/// What the scan-to-scan check found for one edge.
struct OdometryEdgeCheck {
  bool checked = false;     // both scans were there and the check is on
  bool registered = false;  // the scan-to-scan registration passed the verification's checks
  bool snap = false;        // it disagreed with the integrated pose: the edge measures it
  double jump_t = 0.0;      // [m] integrated vs scan-to-scan relative pose (when registered)
  double jump_r = 0.0;      // [rad]
  // The scan-to-scan relative pose (previous_T_current) when registered (odometry_edges.txt).
  Eigen::Isometry3d measured = Eigen::Isometry3d::Identity();
  double seconds = 0.0;  // spent registering
};

struct OdometryEdgeTally {
  int checked = 0;         // edges with both scans
  int registered = 0;      // of those, registered scan to scan
  int snaps = 0;           // of those, measured scan to scan (disagreement beyond the noise)
  int snaps_unclosed = 0;  // of the snaps, back to the integrated edge: no closure tied them
  double seconds = 0.0;
  double max_seconds = 0.0;
};

/// The odometry edge from previous to current (consecutive keyframes of one robot; distance:
/// the path between them). With params.scan_to_scan_edges and both scans kept, current's scan
/// is registered against previous's from the integrated relative pose and, when it differs,
/// from motion (the robot's relative motion over the edge before: a guess without the jump, for
/// a snap beyond the registration's basin); check (optional) says what it found.
PoseEdge odometryEdge(const Keyframe& previous, const Keyframe& current, double distance,
                      const std::optional<Eigen::Isometry3d>& motion,
                      const ConsistencyParams& params, const map::MapConfig& map_config,
                      const odom::OdomConfig& odom_config, OdometryEdgeCheck* check = nullptr);

/// Adds check to tally (an edge that was not checked counts nothing).
void tallyEdge(OdometryEdgeTally& tally, const OdometryEdgeCheck& check);

}  // namespace socc::consistency
