#pragma once
// What a robot that found no pose in the shared map keeps while it maps in its own frame
// (odom_client --own-frame, docs/relocalization.md "Own frame"): its last scans as its
// registration target and as the cloud it keeps matching against the shared map (PosedFrames),
// and keyframes (one thinned scan every few metres) that are integrated into the shared map, in
// order, once the robot is merged into it. Nothing of it reaches the server before the merge.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "socc/gravity_reference.hpp"
#include "socc/odom/frame_bridge.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/posed_frames.hpp"

namespace socc::odom {

/// A kept scan of the own-frame stretch.
struct OwnKeyframe {
  std::int64_t seq = 0;
  std::int64_t utime = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // own_T_sensor (reference time)
  LabeledCloud cloud;                                      // thinned, sensor frame (deskewed)
  std::optional<GravityReference> gravity = std::nullopt;  // the scan's, sent when merged
};

/// Bounds of the own-frame map.
struct OwnFrameLimits {
  std::size_t recent_scans = 10;   // the registration target: the last scans
  double keyframe_distance = 2.0;  // [m] of travel between kept keyframes
  double keyframe_angle = 0.35;    // [rad] of turn between kept keyframes (about 20 deg)
  double keyframe_spacing = 0.2;   // [m] a keyframe's points are thinned to this
  // Beyond: every other keyframe is dropped and the distance between keyframes doubled, so the
  // whole own-frame path stays kept (and searchable, and merged) at a coarser spacing.
  std::size_t max_keyframes = 500;
};

class OwnFrameMap {
 public:
  explicit OwnFrameMap(OwnFrameLimits limits = {});

  /// Adds a healthy registered frame (pose in the own frame): to the target, and as a keyframe
  /// when it is the first or far enough from the last one.
  void add(const FrameEstimate& frame);

  /// The registration target of the next frame (own frame); empty before the first frame.
  LocalMap target() const { return recent_.target(); }
  /// The newest count frames stacked in the newest one's frame (for the shared-map search).
  PreparedScan stacked(std::size_t count, double reference_time) const {
    return recent_.stacked(count, reference_time);
  }
  std::size_t frames() const { return recent_.size(); }
  Eigen::Isometry3d newestPose() const { return recent_.newestPose(); }
  const std::vector<OwnKeyframe>& keyframes() const { return keyframes_; }
  /// Keyframes dropped by max_keyframes (thinning).
  std::size_t droppedKeyframes() const { return dropped_; }
  /// [m] of travel between keyframes now: keyframe_distance, doubled at each thinning.
  double keyframeDistance() const { return keyframe_distance_; }
  /// Memory of the keyframes [bytes] (what grows with the path; the target is bounded).
  std::size_t keyframeBytes() const;
  /// Memory of the last scans of the target [bytes].
  std::size_t recentBytes() const { return recent_.bytes(); }

 private:
  bool isKeyframe(const Eigen::Isometry3d& pose) const;
  /// Every other keyframe dropped (the newest kept), keyframe_distance_ doubled.
  void thin();

  OwnFrameLimits limits_;
  double keyframe_distance_;
  PosedFrames recent_;
  std::vector<OwnKeyframe> keyframes_;
  std::size_t dropped_ = 0;
};

/// The shared map's frame from the own one: the verified pose of a scan in the shared map times
/// the inverse of its own-frame pose (shared_T_own).
Eigen::Isometry3d sharedFromOwn(const Eigen::Isometry3d& verified, const Eigen::Isometry3d& own);

/// The keyframes as they are integrated at the merge: in order, each at bridge.at(seq) * pose;
/// the newest frame (newest, already registered) is appended when it is not the last keyframe, so
/// the server's last pose of the robot is the one its odometry goes on from.
std::vector<OwnKeyframe> mergedKeyframes(const std::vector<OwnKeyframe>& keyframes,
                                         const OwnKeyframe& newest, const FrameBridge& bridge);

}  // namespace socc::odom
