#pragma once
// What the server remembers per robot: last applied seq (for idempotent Integrate), last pose
// (so a restarted client can resume) and the pose history (every applied Integrate's pose).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "socc/pose_history_t.hpp"
#include "socc/robot_state_t.hpp"

namespace socc::service {

class RobotRegistry {
 public:
  /// True when seq was applied before: equal to or lower than the robot's last applied seq.
  bool isDuplicate(const std::string& robot_id, std::int64_t seq) const;
  bool contains(const std::string& robot_id) const { return robots_.count(robot_id) > 0; }
  std::size_t size() const { return robots_.size(); }

  void recordIntegration(const std::string& robot_id, std::int64_t seq, std::int64_t scan_utime,
                         const pose3d_t& pose);
  const robot_state_t* find(const std::string& robot_id) const;
  std::vector<robot_state_t> states() const;  // ordered by robot id
  /// Up to max_poses entries of the robot's history with seq >= from_seq (seq order); truncated
  /// is set when more follow. Empty for an unknown robot.
  pose_history_t history(const std::string& robot_id, std::int64_t from_seq, std::size_t max_poses,
                         bool* truncated) const;
  std::vector<pose_history_t> histories() const;  // ordered by robot id
  /// Replaces everything; histories may be empty (snapshots written before pose histories).
  void assign(const std::vector<robot_state_t>& states,
              const std::vector<pose_history_t>& histories);
  void clear() { robots_.clear(); }

 private:
  struct Robot {
    robot_state_t state;
    pose_history_t history;
  };
  std::map<std::string, Robot> robots_;  // ordered: deterministic snapshots and stats
};

}  // namespace socc::service
