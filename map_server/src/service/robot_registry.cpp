#include "robot_registry.hpp"

#include <algorithm>
#include <cstddef>
#include <type_traits>

#include "plausibility.hpp"
#include "socc/pose_history.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::service {
namespace {

pose_history_t emptyHistory(const std::string& robot_id) {
  pose_history_t h{};
  h.robot_id = robot_id;
  return h;
}

// A history is consistent when every array has num_poses entries (decoded snapshots are).
bool consistent(const pose_history_t& h) {
  return wire::hasCount(h.seq, h.num_poses) && wire::hasCount(h.scan_utime, h.num_poses) &&
         wire::hasRows(h.translation, 3, h.num_poses) &&
         wire::hasRows(h.quaternion, 4, h.num_poses);
}

}  // namespace

bool RobotRegistry::isDuplicate(const std::string& robot_id, std::int64_t seq) const {
  const auto it = robots_.find(robot_id);
  return it != robots_.end() && seq <= it->second.state.last_seq;
}

void RobotRegistry::recordIntegration(const std::string& robot_id, std::int64_t seq,
                                      std::int64_t scan_utime, const pose3d_t& pose) {
  auto [it, inserted] = robots_.try_emplace(robot_id);
  Robot& robot = it->second;
  if (inserted) {
    robot.state.robot_id = robot_id;
    robot.state.integrations = 0;
    robot.history = emptyHistory(robot_id);
  }
  robot.state.last_seq = seq;
  robot.state.last_scan_utime = scan_utime;
  robot.state.last_pose = pose;
  ++robot.state.integrations;
  robot.anchored = true;
  appendPose(robot.history, seq, scan_utime, pose);
}

void RobotRegistry::recordRefusal(const std::string& robot_id) {
  if (const auto it = robots_.find(robot_id); it != robots_.end())
    ++it->second.state.refused_integrations;
}

bool RobotRegistry::recordTracking(const std::string& robot_id, std::int64_t seq,
                                   std::int64_t utime, std::int8_t tracking_state,
                                   const std::string& reason) {
  const auto it = robots_.find(robot_id);
  if (it == robots_.end()) return false;
  Robot& robot = it->second;
  // Back from LOST / RELOCALIZING: the robot found its pose again (in the map), so its next
  // pose is not judged against the one it had before it was lost, which may be wrong.
  if (refusesIntegrations(robot.state.tracking_state) && !refusesIntegrations(tracking_state))
    robot.anchored = false;
  robot.state.tracking_state = tracking_state;
  robot.state.tracking_reason = reason;
  robot.state.tracking_seq = seq;
  robot.state.tracking_utime = utime;
  return true;
}

bool RobotRegistry::anchored(const std::string& robot_id) const {
  const auto it = robots_.find(robot_id);
  return it != robots_.end() && it->second.anchored;
}

const robot_state_t* RobotRegistry::find(const std::string& robot_id) const {
  const auto it = robots_.find(robot_id);
  return it == robots_.end() ? nullptr : &it->second.state;
}

std::vector<robot_state_t> RobotRegistry::states() const {
  std::vector<robot_state_t> out;
  out.reserve(robots_.size());
  for (const auto& [id, robot] : robots_) out.push_back(robot.state);
  return out;
}

pose_history_t RobotRegistry::history(const std::string& robot_id, std::int64_t from_seq,
                                      std::size_t max_poses, bool* truncated) const {
  pose_history_t out = emptyHistory(robot_id);
  if (truncated != nullptr) *truncated = false;
  const auto it = robots_.find(robot_id);
  if (it == robots_.end() || it->second.history.num_poses == 0) return out;
  const pose_history_t& h = it->second.history;
  // Seqs only grow (duplicates are refused), so the history is sorted by seq.
  const auto first = std::lower_bound(h.seq.begin(), h.seq.end(), from_seq) - h.seq.begin();
  const auto last =
      std::min<std::ptrdiff_t>(h.num_poses, first + static_cast<std::ptrdiff_t>(max_poses));
  if (truncated != nullptr) *truncated = last < h.num_poses;
  const auto slice = [&](const auto& column) {
    return std::decay_t<decltype(column)>(column.begin() + first, column.begin() + last);
  };
  out.num_poses = static_cast<std::int32_t>(last - first);
  out.seq = slice(h.seq);
  out.scan_utime = slice(h.scan_utime);
  for (const auto& row : h.translation) out.translation.push_back(slice(row));
  for (const auto& row : h.quaternion) out.quaternion.push_back(slice(row));
  return out;
}

std::vector<pose_history_t> RobotRegistry::histories() const {
  std::vector<pose_history_t> out;
  out.reserve(robots_.size());
  for (const auto& [id, robot] : robots_) out.push_back(robot.history);
  return out;
}

void RobotRegistry::assign(const std::vector<robot_state_t>& states,
                           const std::vector<pose_history_t>& histories) {
  robots_.clear();
  for (const auto& state : states) {
    Robot& robot = robots_[state.robot_id];
    robot.state = state;
    robot.history = emptyHistory(state.robot_id);
  }
  for (const auto& h : histories) {
    const auto it = robots_.find(h.robot_id);
    if (it != robots_.end() && consistent(h)) it->second.history = h;
  }
}

}  // namespace socc::service
