#pragma once
// Which frame each robot's INTEGRATE poses are in, once the map was corrected
// (docs/consistency.md, "Map correction"). A robot integrates in its odometry's frame until the
// server swaps in a grid rebuilt at optimized poses; the robot's next INTEGRATE is still in the
// old frame (its scan was registered against the old grid), so the server moves it by the
// robot's correction and tells the robot in that reply; every later request (higher seq) is in
// the corrected frame. The consistency service keeps seeing each robot's poses in its first
// frame (raw), so its pose graph's odometry edges never see the jump.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace socc::service {

class RobotCorrections {
 public:
  struct Incoming {
    Eigen::Isometry3d raw = Eigen::Isometry3d::Identity();  // in the robot's first frame
    Eigen::Isometry3d map = Eigen::Isometry3d::Identity();  // where it goes into the grid
    std::optional<Eigen::Isometry3d> told;  // the correction this request's reply carries
  };

  /// A new (not duplicate) INTEGRATE of robot at seq with pose as the robot sent it.
  Incoming incoming(const std::string& robot, std::int64_t seq, const Eigen::Isometry3d& pose);
  /// The correction a duplicate of seq must carry again (the first reply may have been lost).
  std::optional<Eigen::Isometry3d> toldWith(const std::string& robot, std::int64_t seq) const;
  /// A new grid: robot's raw poses now belong at correction * raw. Told with its next request.
  void offer(const std::string& robot, const Eigen::Isometry3d& raw_to_map);
  /// raw -> the robot's current poses (identity for a robot never corrected).
  Eigen::Isometry3d frame(const std::string& robot) const;
  /// Robots that were offered a correction and have not integrated since.
  int waiting() const;
  void clear() { robots_.clear(); }
  /// Text for the snapshot (empty when no robot was corrected); parse() restores it and
  /// returns false (changing nothing) when the text does not parse.
  std::string serialize() const;
  bool parse(const std::string& text);

 private:
  struct Robot {
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // raw -> the robot's poses
    std::optional<Eigen::Isometry3d> offered;                 // raw -> map, not told yet
    std::int64_t told_seq = -1;
    Eigen::Isometry3d told = Eigen::Isometry3d::Identity();
  };
  std::map<std::string, Robot> robots_;
};

}  // namespace socc::service
