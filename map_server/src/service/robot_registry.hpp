#pragma once
// What the server remembers per robot: last applied seq (for idempotent Integrate) and last
// pose (so a restarted client can resume).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

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
  void assign(const std::vector<robot_state_t>& states);
  void clear() { robots_.clear(); }

 private:
  std::map<std::string, robot_state_t> robots_;  // ordered: deterministic snapshots and stats
};

}  // namespace socc::service
