#pragma once
// The look back of a robot mapping in its own frame (odom_client --own-frame,
// docs/relocalization.md "Own frame"): its forward search only finds the shared map where the
// robot drives into a place another robot mapped BEFORE it. The other way round, another robot
// reaching the places this one passed, is found by searching the shared map for the robot's kept
// scans (OwnFrameMap keyframes) again: the sweep walks over them from the oldest, a pair of
// adjacent windows of stack_scans kept scans at a time (two consecutive searches, so that a
// place can be confirmed as the forward search confirms it), then skips gap metres of path;
// while the last search's best place is in the map (not yet confirmed: ambiguous, or leading
// for too few searches) it goes on window by window instead, as a robot driving there would.
// When it has passed the newest window it starts again from the oldest (the map has grown).
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

#include "socc/odom/odometry.hpp"
#include "socc/odom/own_frame_map.hpp"

namespace socc::odom {

/// One search of the sweep: a window of kept scans stacked in its newest one's frame.
struct KeptPlaceSearch {
  PreparedScan stacked;
  int scans = 0;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();    // previous search's scan to this
  Eigen::Isometry3d own_pose = Eigen::Isometry3d::Identity();  // the newest stacked scan's
  bool sweep_start = false;  // the first of a sweep: places followed before are stale
};

class KeptPlaceSweep {
 public:
  /// stack_scans: kept scans per window (>= 1); gap: [m] of kept path skipped after each pair.
  KeptPlaceSweep(int stack_scans, double gap);

  /// The next window of own's kept scans (the newest stack_scans ones excluded: the forward
  /// search covers the robot's current place); nullopt when there are too few. in_map: the last
  /// search's best place explained enough of its window (the next window follows it).
  std::optional<KeptPlaceSearch> next(const OwnFrameMap& own, double reference_time,
                                      bool in_map = false);
  /// The next call starts a new sweep from the oldest kept scan.
  void restart();

 private:
  int stack_scans_;
  double gap_;
  std::optional<std::int64_t> last_seq_;        // the previous window's newest kept scan
  std::optional<Eigen::Isometry3d> last_pose_;  // its pose
  int run_ = 0;                                 // adjacent windows searched since the last gap
};

}  // namespace socc::odom
