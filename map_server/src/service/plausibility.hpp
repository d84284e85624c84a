#pragma once
// Which INTEGRATEs of a known robot may reach the shared map (issue 11 item 4). A diverged
// registration shows as a pose no robot can reach from its last accepted one in the time
// between the two scans; a robot that reported LOST or RELOCALIZING has no pose to give. Both
// are refused with FAILED_PRECONDITION before anything is journaled or applied.
#include <cstdint>
#include <string>

#include "service_config.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/robot_state_t.hpp"
#include "status.hpp"

namespace socc::service {

/// Empty when a sensor can move from `from` at from_utime to `to` at to_utime [us] within
/// limits: distance <= max_linear_speed * dt + linear_slack and rotation angle <=
/// max_angular_speed * dt + angular_slack, with dt = max(0, to_utime - from_utime) (equal or
/// backward scan times allow the slacks only). Else the reason, e.g. "pose jumps 37.2 m in
/// 0.1 s (372 m/s > max 40 m/s)".
std::string implausibleMotion(const pose3d_t& from, std::int64_t from_utime, const pose3d_t& to,
                              std::int64_t to_utime, const PlausibilityLimits& limits);

/// OK when request may be applied for robot (a robot with an accepted INTEGRATE): it has not
/// reported LOST or RELOCALIZING and, while anchored, its pose is plausible against the last
/// accepted pose and scan time. Not anchored (it reported TRACKING or DEGRADED after LOST or
/// RELOCALIZING), the pose starts anew like a robot's first.
Status admitIntegrate(const robot_state_t& robot, bool anchored, const integrate_request_t& request,
                      const PlausibilityLimits& limits);

/// True for the tracking states in which a robot's INTEGRATEs are refused.
bool refusesIntegrations(std::int8_t tracking_state);

}  // namespace socc::service
