#pragma once
// Which frame each robot's INTEGRATE poses are in, once the map was corrected
// (docs/consistency.md, "Map correction"). A robot integrates in its odometry's frame until the
// server swaps in a grid rebuilt at optimized poses: a generation of frames, in which each
// corrected robot's raw poses belong at its correction x raw. A request names the map instance
// whose frame its pose is in (integrate_request_t::map_epoch: the grid the scan was registered
// against); the server knows each instance's generation, so a pose of an older generation is
// moved into the current one and the robot is told in that reply, and a pose already in the
// current generation (a robot that relocalized against the corrected grid, or registered
// against it before its next Integrate) is taken as it is. A request of an unknown instance
// (map_epoch 0: an older client; or an instance forgotten) is in the frame the robot was last
// told. The consistency service keeps seeing each robot's poses in its first frame (raw), so its
// pose graph's odometry edges never see the jump.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace socc::service {

class RobotCorrections {
 public:
  struct Incoming {
    Eigen::Isometry3d raw = Eigen::Isometry3d::Identity();  // in the robot's first frame
    Eigen::Isometry3d map = Eigen::Isometry3d::Identity();  // where it goes into the grid
    std::optional<Eigen::Isometry3d> told;  // the correction this request's reply carries
  };

  /// The map instance `epoch` (chunk_reply_t::map_epoch) answers from now on, in the current
  /// generation: a new or loaded grid, a restart, a clear.
  void serving(std::int64_t epoch);
  /// A grid rebuilt at corrected poses, instance `epoch`, answers from now on: a new generation
  /// in which each robot's raw poses belong at raw_to_map * raw (robots not named keep theirs).
  void corrected(std::int64_t epoch, const std::map<std::string, Eigen::Isometry3d>& raw_to_map);
  /// A new (not duplicate) INTEGRATE of robot at seq with pose as the robot sent it, in the
  /// frame of map instance pose_epoch (0: unknown).
  Incoming incoming(const std::string& robot, std::int64_t seq, const Eigen::Isometry3d& pose,
                    std::int64_t pose_epoch);
  /// The correction a duplicate of seq must carry again (the first reply may have been lost).
  std::optional<Eigen::Isometry3d> toldWith(const std::string& robot, std::int64_t seq) const;
  /// raw -> the robot's poses in the current grid (identity for a robot never corrected).
  Eigen::Isometry3d frame(const std::string& robot) const;
  /// Robots corrected since they last integrated (told with their next request).
  int waiting() const;
  /// Forgets every robot and instance: a cleared map starts a first generation again.
  void clear() { *this = RobotCorrections(); }
  /// Text for the snapshot (empty when nothing was ever corrected); parse() restores it (also
  /// the text of servers before map instances were named) and returns false (changing nothing)
  /// when the text does not parse.
  std::string serialize() const;
  bool parse(const std::string& text);

 private:
  struct Robot {
    std::map<int, Eigen::Isometry3d> frames;  // generation -> raw -> its grid; identity before
    int generation = 0;  // of the frame its requests of an unknown instance are in (last told)
    std::int64_t told_seq = -1;
    Eigen::Isometry3d told = Eigen::Isometry3d::Identity();
  };
  static Eigen::Isometry3d frameAt(const Robot& robot, int generation);
  int generationOf(const Robot& robot, std::int64_t epoch) const;
  void keepNeededFrames(Robot& robot) const;
  bool parseLegacy(const std::string& text);

  int generation_ = 0;                  // corrected grids swapped in so far
  std::map<std::int64_t, int> epochs_;  // map instance -> its generation (the newest kMaxEpochs)
  std::map<std::string, Robot> robots_;
};

}  // namespace socc::service
