#include "robot_corrections.hpp"

namespace socc::service {

RobotCorrections::Incoming RobotCorrections::incoming(const std::string& robot, std::int64_t seq,
                                                      const Eigen::Isometry3d& pose) {
  Incoming out;
  const auto it = robots_.find(robot);
  if (it == robots_.end()) {  // never corrected: all its poses are raw and in the grid's frame
    out.raw = pose;
    out.map = pose;
    return out;
  }
  Robot& r = it->second;
  out.raw = r.frame.inverse() * pose;
  out.map = pose;
  if (r.offered) {
    // Registered against the old grid: moved into the new one, and the robot is told.
    out.map = *r.offered * out.raw;
    r.told = *r.offered * r.frame.inverse();
    r.told_seq = seq;
    r.frame = *r.offered;
    r.offered.reset();
    out.told = r.told;
  }
  return out;
}

std::optional<Eigen::Isometry3d> RobotCorrections::toldWith(const std::string& robot,
                                                            std::int64_t seq) const {
  const auto it = robots_.find(robot);
  if (it == robots_.end() || it->second.told_seq != seq) return std::nullopt;
  return it->second.told;
}

void RobotCorrections::offer(const std::string& robot, const Eigen::Isometry3d& raw_to_map) {
  robots_[robot].offered = raw_to_map;
}

int RobotCorrections::waiting() const {
  int n = 0;
  for (const auto& [name, r] : robots_) n += r.offered ? 1 : 0;
  return n;
}

}  // namespace socc::service
