#include "robot_registry.hpp"

namespace socc::service {

bool RobotRegistry::isDuplicate(const std::string& robot_id, std::int64_t seq) const {
  const auto it = robots_.find(robot_id);
  return it != robots_.end() && seq <= it->second.last_seq;
}

void RobotRegistry::recordIntegration(const std::string& robot_id, std::int64_t seq,
                                      std::int64_t scan_utime, const pose3d_t& pose) {
  auto [it, inserted] = robots_.try_emplace(robot_id);
  robot_state_t& state = it->second;
  if (inserted) {
    state.robot_id = robot_id;
    state.integrations = 0;
  }
  state.last_seq = seq;
  state.last_scan_utime = scan_utime;
  state.last_pose = pose;
  ++state.integrations;
}

const robot_state_t* RobotRegistry::find(const std::string& robot_id) const {
  const auto it = robots_.find(robot_id);
  return it == robots_.end() ? nullptr : &it->second;
}

std::vector<robot_state_t> RobotRegistry::states() const {
  std::vector<robot_state_t> out;
  out.reserve(robots_.size());
  for (const auto& [id, state] : robots_) out.push_back(state);
  return out;
}

void RobotRegistry::assign(const std::vector<robot_state_t>& states) {
  robots_.clear();
  for (const auto& state : states) robots_[state.robot_id] = state;
}

}  // namespace socc::service
