#include "plausibility.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "socc/robot_status_request_t.hpp"
#include "socc/rpc/status_names.hpp"

namespace socc::service {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

Eigen::Quaterniond rotation(const pose3d_t& pose) {
  const double* q = pose.quaternion;  // w, x, y, z
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
}

// "pose jumps 37.2 m in 0.1 s (372 m/s > max 40 m/s)"; without time passing, the slack.
std::string describe(const char* verb, double amount, const char* unit, double dt, double max_rate,
                     double slack) {
  char text[192];
  if (dt > 0.0)
    std::snprintf(text, sizeof(text), "pose %s %.1f %s in %.3g s (%.3g %s/s > max %.3g %s/s)", verb,
                  amount, unit, dt, amount / dt, unit, max_rate, unit);
  else
    std::snprintf(text, sizeof(text),
                  "pose %s %.1f %s while scan_utime does not advance (%.3g s; at most %.3g %s "
                  "without time passing)",
                  verb, amount, unit, dt, slack, unit);
  return text;
}

}  // namespace

bool refusesIntegrations(std::int8_t tracking_state) {
  return tracking_state == robot_status_request_t::LOST ||
         tracking_state == robot_status_request_t::RELOCALIZING;
}

std::string implausibleMotion(const pose3d_t& from, std::int64_t from_utime, const pose3d_t& to,
                              std::int64_t to_utime, const PlausibilityLimits& limits) {
  // In double: the difference of two arbitrary int64 scan times could overflow.
  const double dt = (static_cast<double>(to_utime) - static_cast<double>(from_utime)) * 1e-6;
  const double elapsed = std::max(dt, 0.0);
  const Eigen::Vector3d step(to.translation[0] - from.translation[0],
                             to.translation[1] - from.translation[1],
                             to.translation[2] - from.translation[2]);
  const double distance = step.norm();
  if (distance > limits.max_linear_speed * elapsed + limits.linear_slack)
    return describe("jumps", distance, "m", dt, limits.max_linear_speed, limits.linear_slack);
  const double angle = rotation(from).angularDistance(rotation(to)) * kRadToDeg;
  if (angle > limits.max_angular_speed * elapsed + limits.angular_slack)
    return describe("turns", angle, "deg", dt, limits.max_angular_speed, limits.angular_slack);
  return {};
}

Status admitIntegrate(const robot_state_t& robot, bool anchored, const integrate_request_t& request,
                      const PlausibilityLimits& limits) {
  if (refusesIntegrations(robot.tracking_state)) {
    std::string why = "robot " + robot.robot_id + " reported " +
                      rpc::trackingStateName(robot.tracking_state) + " at seq " +
                      std::to_string(robot.tracking_seq);
    if (!robot.tracking_reason.empty()) why += " (" + robot.tracking_reason + ")";
    return Status::failedPrecondition(why + "; INTEGRATE refused until it reports TRACKING");
  }
  if (!anchored || !limits.enabled) return {};
  const std::string why = implausibleMotion(robot.last_pose, robot.last_scan_utime,
                                            request.sensor_pose, request.scan_utime, limits);
  if (why.empty()) return {};
  return Status::failedPrecondition(why + " from robot " + robot.robot_id +
                                    "'s last accepted pose (seq " + std::to_string(robot.last_seq) +
                                    ")");
}

}  // namespace socc::service
