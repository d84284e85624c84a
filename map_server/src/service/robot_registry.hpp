#pragma once
// What the server remembers per robot: last applied seq (for idempotent Integrate), last pose
// (so a restarted client can resume), the pose history (every applied Integrate's pose) and
// the tracking state the robot last reported (ROBOT_STATUS).
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
  std::size_t size() const { return robots_.size(); }

  void recordIntegration(const std::string& robot_id, std::int64_t seq, std::int64_t scan_utime,
                         const pose3d_t& pose);
  /// An INTEGRATE of the robot was refused (FAILED_PRECONDITION): only counted.
  void recordRefusal(const std::string& robot_id);
  /// Stores a tracking report; false (nothing stored) for a robot without an accepted
  /// INTEGRATE. TRACKING or DEGRADED after LOST or RELOCALIZING un-anchors the robot.
  bool recordTracking(const std::string& robot_id, std::int64_t seq, std::int64_t utime,
                      std::int8_t tracking_state, const std::string& reason);
  /// False from a recovery report (see recordTracking) until the next accepted INTEGRATE:
  /// its last pose is then no reference for the plausibility check. In memory only.
  bool anchored(const std::string& robot_id) const;
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
    bool anchored = true;
  };
  std::map<std::string, Robot> robots_;  // ordered: deterministic snapshots and stats
};

}  // namespace socc::service
