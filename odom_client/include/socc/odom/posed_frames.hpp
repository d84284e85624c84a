#pragma once
// A robot's last few scans with their poses in one frame (its private one), thinned, as a
// registration target and as one stacked cloud. What ScanStack (relocalization) and OwnFrameMap
// (a robot mapping in its own frame) register against and match against the shared map.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "socc/odom/local_map.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/scan_map.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

/// cloud thinned to spacing (labels kept, point times dropped): what a kept scan holds.
LabeledCloud thinnedCloud(const LabeledCloud& cloud, double spacing);

class PosedFrames {
 public:
  /// Keeps at most max_frames frames.
  explicit PosedFrames(std::size_t max_frames);

  /// Adds a registered frame (its deskewed cloud, thinned, and its pose); drops the oldest
  /// beyond max_frames.
  void push(const FrameEstimate& frame);
  void clear();

  std::size_t size() const { return frames_.size(); }
  /// Pose of the newest frame (identity when empty).
  Eigen::Isometry3d newestPose() const;
  /// Motion from the frame before the newest to the newest (previous_T_newest); identity with
  /// fewer than two frames.
  const Eigen::Isometry3d& lastMotion() const { return last_motion_; }
  /// The frames as a registration target (their frame), voxels of the map server's size.
  LocalMap target() const;
  /// The newest count frames in the newest one's frame, as one scan with its seq and stamp (no
  /// point times; mid_time: reference_time, where the deskewed points are).
  PreparedScan stacked(std::size_t count, double reference_time) const;
  /// Memory of the kept clouds and their voxels [bytes].
  std::size_t bytes() const;

 private:
  struct Frame {
    LabeledCloud cloud;      // thinned, sensor frame at the reference time
    Eigen::Isometry3d pose;  // the frames' common frame
    std::int64_t seq = 0;
    std::int64_t utime = 0;
    // The cloud's voxels in the common frame, made once: the target merges them every frame
    // (re-voxelizing every kept cloud was most of an own-frame robot's time a scan).
    std::vector<CloudVoxel> voxels;
  };
  std::size_t max_frames_;
  std::deque<Frame> frames_;
  Eigen::Isometry3d last_motion_ = Eigen::Isometry3d::Identity();
};

/// Appends cloud moved by pose to out.
void appendMoved(const LabeledCloud& cloud, const Eigen::Isometry3d& pose, LabeledCloud& out);

/// Bytes held by a cloud's points and labels.
std::size_t cloudBytes(const LabeledCloud& cloud);

}  // namespace socc::odom
