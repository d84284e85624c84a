#pragma once
// The last few scans of a robot that does not know where it is, registered to each other by its
// own odometry (in a private frame; nothing goes to the shared map) and stacked into one cloud in
// the frame of the newest: what relocalization matches against the map where one scan is not
// distinctive (a street seen from one spot looks like many others; a few metres of it less so).
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>

#include "socc/odom/odom_config.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/posed_frames.hpp"

namespace socc::odom {

class ScanStack {
 public:
  /// Keeps at most max_scans scans.
  ScanStack(const OdomConfig& config, std::size_t max_scans);

  /// Registers scan against the stacked scans before it and adds it. False when its odometry is
  /// not trusted (unhealthy): the stack then starts over from this scan. The first scan of a
  /// sensor with point times waits for the next (Odometry holds it): nothing is stacked then.
  bool add(const PreparedScan& scan);

  /// Scans stacked (0 before the first is registered).
  std::size_t size() const { return frames_.size(); }
  /// The stacked scans in the newest one's frame (deskewed, at its reference time), as one scan
  /// with the newest one's seq and stamp (no point times).
  PreparedScan cloud() const;
  /// Motion from the previous newest scan to the newest (newest_T_previous inverted:
  /// previous_T_newest); identity after a restart.
  const Eigen::Isometry3d& lastMotion() const { return frames_.lastMotion(); }
  /// True when add() started the stack over (a restart drops the places matched so far).
  bool restarted() const { return restarted_; }

 private:
  void restart();

  OdomConfig config_;
  std::optional<Odometry> odometry_;
  PosedFrames frames_;  // private frame
  bool restarted_ = false;
};

}  // namespace socc::odom
