#pragma once
// The per-robot odometry state machine (no I/O, no map): constant-velocity prediction,
// preprocessing (range filter, deskew, semantic adaptive downsampling), registration against
// the current frame's LocalMap, and the KISS-ICP threshold and velocity updates.
#include <Eigen/Geometry>
#include <array>

#include "socc/odom/adaptive_threshold.hpp"
#include "socc/odom/local_map.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/registration.hpp"
#include "socc/odom/voxel_downsampling.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

struct PreparedScan {
  LabeledCloud full;         // range-filtered, deskewed (what is integrated into the map)
  LabeledCloud downsampled;  // semantic adaptive voxel means (what is registered)
  double voxel_size = 0.0;   // v_adapt used
};

struct FrameEstimate {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // map_T_sensor
  RegistrationResult registration;
  double sigma = 0.0;       // threshold used for this frame
  bool registered = false;  // false: the map was too small, the prediction was kept
};

class Odometry {
 public:
  /// initial_pose_known: the first scan's pose is given (e.g. --initial-pose in a shared map):
  /// that scan is integrated at it without registration, unless config.refine_initial_pose.
  Odometry(const OdomConfig& config, const Eigen::Isometry3d& initial_pose,
           bool initial_pose_known = false);

  /// frame_period: time since the previous scan [s] (the deskew's velocity reference).
  /// Throws std::invalid_argument when the cloud is inconsistent (see checkCloud).
  PreparedScan prepare(const LabeledCloud& raw, double frame_period);

  /// Pose predicted for the next frame: last pose * last relative motion.
  Eigen::Isometry3d predictedPose() const;

  /// Registers the prepared scan against map from the prediction and advances the state.
  FrameEstimate registerFrame(const PreparedScan& scan, const LocalMap& map);

  /// Restarts from pose with zero velocity and the initial threshold (e.g. --resume).
  void reset(const Eigen::Isometry3d& pose);

  const Eigen::Isometry3d& pose() const { return pose_; }
  const Eigen::Isometry3d& velocity() const { return velocity_; }
  double sigma() const { return threshold_.sigma(); }

 private:
  // Coarse-to-fine passes after the first registration while the threshold is uncalibrated.
  void refine(const PreparedScan& scan, const LocalMap& map, FrameEstimate& out) const;

  OdomConfig config_;
  std::array<double, kNumClasses> class_factor_;
  RegistrationParams params_;
  AdaptiveThreshold threshold_;
  AdaptiveVoxelSize voxel_size_;
  Eigen::Isometry3d pose_;
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // relative motion per frame
  // The first frame after a (re)start has no motion model: its correction measures the error of
  // the given initial pose, not of the model, so it must not shrink the adaptive threshold.
  bool has_motion_model_ = false;
  // A robot joining a shared map often sees its surroundings only as a few far-away scans of
  // other robots; registering against those can move an exact given pose by decimetres, and the
  // first scan integrated there would carry that error into everyone's map.
  bool keep_first_pose_ = false;
};

}  // namespace socc::odom
