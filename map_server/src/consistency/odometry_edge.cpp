#include "odometry_edge.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "socc/odom/odometry.hpp"
#include "socc/odom/relocalization.hpp"
#include "submap_access.hpp"

namespace socc::consistency {
namespace {

bool differs(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double min_t, double min_r) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() > min_t || Eigen::AngleAxisd(d.linear()).angle() > min_r;
}

// A snap is the client pulled onto old walls: a shift and a turn about the sensor's up axis.
// Roll and pitch are left out: the two measurements disagree there by their noise (the body's
// pitch and roll within a sweep: up to 0.8 deg on the realistic preset, where the heading
// agrees within 0.1 deg), and gravity references hold them.
bool snapped(const Eigen::Isometry3d& integrated, const Eigen::Isometry3d& measured,
             const ConsistencyParams& params) {
  const Eigen::Isometry3d d = integrated.inverse() * measured;
  const Eigen::AngleAxisd turn(d.linear());
  return d.translation().norm() > params.snap_min_t ||
         std::abs(turn.angle() * turn.axis().z()) > params.snap_min_r;
}

// current's pose in previous's frame from its scan registered against previous's scan alone
// (exactly the closure verification's checks; two guesses that converge to different places
// are ambiguous and refused).
std::optional<Eigen::Isometry3d> scanToScan(const Keyframe& previous, const Keyframe& current,
                                            const std::vector<Eigen::Isometry3d>& guesses,
                                            const ConsistencyParams& params,
                                            const map::MapConfig& map_config,
                                            const odom::OdomConfig& odom_config) {
  LabeledCloud cloud;
  cloud.points = current.points;
  const odom::PreparedScan scan = odom::prepareScan(odom_config, cloud, current.seq, current.utime);
  SubmapAccess submap(map_config, {{&previous.points, Eigen::Isometry3d::Identity()}}, guesses,
                      params.chunk_radius);
  odom::OdomConfig config = odom_config;
  config.relocalize_candidates = static_cast<int>(guesses.size());
  return odom::relocalize(config, scan, submap, std::nullopt).pose;
}

}  // namespace

PoseEdge odometryEdge(const Keyframe& previous, const Keyframe& current, double distance,
                      const std::optional<Eigen::Isometry3d>& motion,
                      const ConsistencyParams& params, const map::MapConfig& map_config,
                      const odom::OdomConfig& odom_config, OdometryEdgeCheck* check) {
  if (check) *check = {};
  PoseEdge edge;
  edge.from = previous.id;
  edge.to = current.id;
  edge.relative = previous.odom_pose.inverse() * current.odom_pose;
  edge.information =
      isotropicInformation(params.odometry_sigma_t + params.odometry_sigma_t_per_m * distance,
                           params.odometry_sigma_r + params.odometry_sigma_r_per_m * distance);
  if (!params.scan_to_scan_edges || previous.points.empty() || current.points.empty()) return edge;
  const auto start = std::chrono::steady_clock::now();
  std::optional<Eigen::Isometry3d> measured;
  try {
    std::vector<Eigen::Isometry3d> guesses = {edge.relative};
    if (motion && differs(*motion, edge.relative, params.snap_min_t, params.snap_min_r))
      guesses.push_back(*motion);
    measured = scanToScan(previous, current, guesses, params, map_config, odom_config);
  } catch (const std::exception&) {
    // A scan the registration cannot take (bad cloud): the integrated edge stays.
  }
  OdometryEdgeCheck c;
  c.checked = true;
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (measured) {
    const Eigen::Isometry3d d = edge.relative.inverse() * *measured;
    c.registered = true;
    c.measured = *measured;
    c.jump_t = d.translation().norm();
    c.jump_r = Eigen::AngleAxisd(d.linear()).angle();
    c.snap = snapped(edge.relative, *measured, params);
    if (c.snap) edge.relative = *measured;
  }
  if (check) *check = c;
  return edge;
}

void tallyEdge(OdometryEdgeTally& tally, const OdometryEdgeCheck& check) {
  if (!check.checked) return;
  ++tally.checked;
  tally.registered += check.registered ? 1 : 0;
  tally.snaps += check.snap ? 1 : 0;
  tally.seconds += check.seconds;
  tally.max_seconds = std::max(tally.max_seconds, check.seconds);
}

}  // namespace socc::consistency
