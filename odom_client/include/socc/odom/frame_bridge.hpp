#pragma once
// How a robot's own frame moves into the shared one at its merge (odom_client --own-frame,
// docs/relocalization.md "Own frame"). One placed scan gives one rigid move for the whole
// own-frame stretch, and the odometry's drift along the stretch then shows at its far end. When
// two scans were placed (a kept scan found looking back, and the robot's newest place), the move
// is each one's at and beyond it and, in between, interpolated by the own-frame path travelled:
// the drift grows with the path, and both places land where the shared map has them.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace socc::odom {

class FrameBridge {
 public:
  /// One placement: shared_T_own for every scan.
  explicit FrameBridge(const Eigen::Isometry3d& shared_T_own);
  /// Two placements along the own-frame path (seqs increasing, positions in the own frame):
  /// from (its seq and shared_T_own) at and before from_seq, to at and after to_seq.
  FrameBridge(const std::vector<std::int64_t>& seqs, const std::vector<Eigen::Vector3d>& positions,
              std::int64_t from_seq, const Eigen::Isometry3d& from, std::int64_t to_seq,
              const Eigen::Isometry3d& to);

  /// The move of the own-frame scan seq into the shared frame.
  Eigen::Isometry3d at(std::int64_t seq) const;
  /// Own-frame path between the two placements [m] (0 with one).
  double bridgedPath() const { return to_path_ - from_path_; }
  /// How far the two placements disagree at the newer one [m]: the drift bridged (0 with one).
  double bridgedDrift() const;

 private:
  /// Own-frame path travelled up to seq [m].
  double pathAt(std::int64_t seq) const;

  std::vector<std::int64_t> seqs_;
  std::vector<double> path_;  // travelled up to seqs_[i]
  Eigen::Isometry3d from_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d to_ = Eigen::Isometry3d::Identity();
  std::int64_t to_seq_ = 0;
  double from_path_ = 0.0;
  double to_path_ = 0.0;
  Eigen::Vector3d to_position_ = Eigen::Vector3d::Zero();  // own-frame position at to_seq
};

}  // namespace socc::odom
