#pragma once
// The per-robot odometry state machine (no I/O, no map): constant-velocity prediction,
// preprocessing (range filter, per-point times), registration of each sweep at its middle with
// deskew iterated on the frame's own motion, per-frame health, and the KISS-ICP threshold update.
//
// Poses are estimated at the middle of each sweep (see sweepMidTime: there a wrong deskew twist
// stretches the scan instead of shifting it, so deskew and registration do not feed each other's
// errors) and reported at the scan time + deskew_reference_time. The first scan of a run that
// carries per-point times is held until the second gives the motion to deskew it with: nothing
// enters the map deskewed with a guessed motion.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "socc/gravity_reference.hpp"
#include "socc/odom/adaptive_threshold.hpp"
#include "socc/odom/frame_health.hpp"
#include "socc/odom/frame_period.hpp"
#include "socc/odom/local_map.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/range_calibration.hpp"
#include "socc/odom/registration.hpp"
#include "socc/odom/se3.hpp"
#include "socc/odom/tilt_reference.hpp"
#include "socc/odom/voxel_downsampling.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

struct PreparedScan {
  LabeledCloud cloud;      // range-filtered, sensor frame, per-point times kept (not deskewed)
  std::int64_t seq = 0;    // copied into the estimate
  std::int64_t utime = 0;  // scan timestamp [us]
  double mid_time = 0.0;   // [s, relative to utime] middle of the sweep (0 without times)
  std::optional<GravityReference> gravity = std::nullopt;  // the source's, passed on
  double time() const { return utime * 1e-6 + mid_time; }  // [s] of the mid-sweep pose
};

/// Range filter, labels, per-point times (recorded, or from the azimuth when configured): what
/// the scan needs before registration, from the configuration alone (no odometry state).
/// Throws std::invalid_argument when the cloud is inconsistent (see checkCloud).
PreparedScan prepareScan(const OdomConfig& config, const LabeledCloud& raw, std::int64_t seq,
                         std::int64_t utime);

struct FrameEstimate {
  std::int64_t seq = 0;
  std::int64_t utime = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // map_T_sensor at the reference time
  LabeledCloud cloud;  // deskewed to the reference time, no times: what is integrated
  std::optional<GravityReference> gravity = std::nullopt;  // the scan's, sent with its Integrate
  RegistrationResult registration;
  FrameHealth health;
  double sigma = 0.0;                 // threshold used for this frame
  double voxel_size = 0.0;            // v_adapt used
  std::size_t registered_points = 0;  // after downsampling
  int deskew_passes = 0;
  bool registered = false;  // false: the map was too small (or a given pose), prediction kept
  bool held = false;        // the first scan, waiting for the second (see takeReleasedFrame)
  bool retried = false;     // healthy only at the second attempt (wider threshold)
  double fitness = 0.0;     // registerAt: share of the downsampled scan within 0.5 m of the map
};

class Odometry {
 public:
  /// initial_pose_known: the first scan's pose is given (e.g. --initial-pose in a shared map):
  /// that scan is integrated at it without registration, unless config.refine_initial_pose.
  Odometry(const OdomConfig& config, const Eigen::Isometry3d& initial_pose,
           bool initial_pose_known = false);

  /// prepareScan with this odometry's configuration.
  PreparedScan prepare(const LabeledCloud& raw, std::int64_t seq, std::int64_t utime) const;

  /// Pose predicted at the middle of scan's sweep (constant velocity).
  Eigen::Isometry3d predictedPose(const PreparedScan& scan) const;
  /// Position predicted seconds after the last registered sweep's middle (constant velocity).
  Eigen::Vector3d predictedPosition(double seconds) const;

  /// Registers scan against map and advances the state. An unhealthy estimate does not move the
  /// state: the pose follows the prediction and the estimate says why (health.problem).
  FrameEstimate registerFrame(const PreparedScan& scan, const LocalMap& map);

  /// More evidence for a registration whose motion surprised (FrameHealth::surprise): why the
  /// estimate contradicts the map (e.g. its points in the map's free space), empty when it does
  /// not. Called before the state advances; without one a surprise is only reported.
  using SurpriseCheck = std::function<std::string(const FrameEstimate&)>;
  void setSurpriseCheck(SurpriseCheck check) { surprise_check_ = std::move(check); }

  /// Registers scan against map from guess alone (no motion model, no deskew, the state is not
  /// advanced): verifying a candidate pose (relocalization). Sets health and fitness.
  FrameEstimate registerAt(const PreparedScan& scan, const LocalMap& map,
                           const Eigen::Isometry3d& guess);

  /// The held first scan, once the second registration has given its motion (at most once).
  std::optional<FrameEstimate> takeReleasedFrame();

  /// The map was corrected (docs/consistency.md): corrected = correction * pose for every pose
  /// so far. Moves the state's pose (and a released first frame); the motion (a body twist),
  /// the period and the threshold stay, so the next registration goes on as if nothing happened.
  /// The map's up (gravity in the map frame) stays: the service rebuilt the map in the same
  /// frame, levelled by the robots' gravity references, so the correction's tilt is the drift
  /// it removed, not a turn of gravity.
  void correct(const Eigen::Isometry3d& correction);
  /// The map frame itself changed (an own-frame robot merged into the shared map):
  /// new_T_old * pose for every pose so far, as correct() does, and the map's up turns with it.
  void moveFrame(const Eigen::Isometry3d& new_T_old);
  /// The gravity reference's hold on roll and pitch (the map's up, the filter's state).
  const TiltReference& tiltReference() const { return tilt_; }
  /// Restarts from pose with zero velocity and the initial threshold (e.g. --resume).
  void reset(const Eigen::Isometry3d& pose);

  double sigma() const { return threshold_.sigma(); }
  /// The per-laser range calibration (none when config.range_calibration is off).
  const RangeCalibration* rangeCalibration() const {
    return range_calibration_ ? &*range_calibration_ : nullptr;
  }
  /// [s] the time between scans as their stamps show it (frame_period.hpp).
  double framePeriod() const { return period_.period(); }
  /// Body twist per second of the constant-velocity model (translation first).
  const Vector6d& twist() const { return twist_; }

 private:
  struct Sweep;  // one deskew + registration pass's result
  // registerFrame of a scan whose ranges the calibration corrected.
  FrameEstimate registerCorrected(const PreparedScan& scan, const LocalMap& map);
  // params: params_ when none.
  Sweep registerSweep(const PreparedScan& scan, const LocalMap& map, const Eigen::Isometry3d& guess,
                      const Vector6d& twist, double sigma, const SweepTwistPrior* prior = nullptr,
                      const RegistrationParams* params = nullptr);
  // The continuous-time registration's prior for a sweep deskewed with deskew_twist (none when
  // sweep_twist_sigma_* are 0).
  std::optional<SweepTwistPrior> sweepPrior(const Vector6d& deskew_twist,
                                            const Vector6d& measured) const;
  // Semantic, adaptive voxel size; the points deskewed by motion first, when given.
  LabeledCloud downsample(const LabeledCloud& cloud, const SweepMotion* motion = nullptr);
  bool registrable(const LocalMap& map) const;  // holds at least min_map_points
  Eigen::Isometry3d searchFirstMotion(const PreparedScan& scan, const LocalMap& map,
                                      const Eigen::Isometry3d& from, double dt, double sigma);
  // Registers from the constant-velocity prediction with model_twist (twist_, or zero: the robot
  // stood still); a degenerate result again with its weakest direction held at the prediction.
  FrameEstimate estimate(const PreparedScan& scan, const LocalMap& map, double sigma,
                         const Vector6d& model_twist);
  // One registration (with its deskew passes) from that prediction, with params.
  FrameEstimate estimateWith(const PreparedScan& scan, const LocalMap& map, double sigma,
                             const Vector6d& model_twist, const RegistrationParams& params);
  // The registration of a scan with the model's fallbacks: a wider threshold, and after a time
  // gap the robot standing still.
  FrameEstimate estimateWithRetries(const PreparedScan& scan, const LocalMap& map);
  FrameEstimate bootstrap(const PreparedScan& scan, const LocalMap& map);
  FrameEstimate unregistered(const PreparedScan& scan, const Eigen::Isometry3d& mid_pose);
  void finish(const PreparedScan& scan, const Eigen::Isometry3d& mid_pose, const Vector6d& twist,
              FrameEstimate& out) const;
  void judge(const PreparedScan& scan, FrameEstimate& out) const;
  void advance(const PreparedScan& scan, const FrameEstimate& out, const Eigen::Isometry3d& mid);
  Vector6d twistTo(const Eigen::Isometry3d& mid_pose, double time) const;
  // The scan's gravity reference as the sensor's up at the sweep's middle (the reference is
  // taken at the scan time; twist turns it to the pose's instant); none without one.
  std::optional<Eigen::Vector3d> upAtMid(const PreparedScan& scan, const Vector6d& twist) const;

  OdomConfig config_;
  std::array<double, kNumClasses> class_factor_;
  RegistrationParams params_;
  AdaptiveThreshold threshold_;
  AdaptiveVoxelSize voxel_size_;
  FramePeriod period_;
  Eigen::Isometry3d pose_;  // map_T_sensor at time_ (middle of the last sweep)
  double time_ = -1.0;      // [s]; negative: no frame yet (pose_ is the initial pose)
  Vector6d twist_ = Vector6d::Zero();
  bool twist_known_ = false;  // twist_ was measured between two registered frames
  // The first frame after a (re)start has no motion model: its correction measures the error of
  // the given initial pose, not of the model, so it must not shrink the adaptive threshold.
  bool has_motion_model_ = false;
  // A robot joining a shared map often sees its surroundings only as a few far-away scans of
  // other robots; registering against those can move an exact given pose by decimetres, and the
  // first scan integrated there would carry that error into everyone's map.
  bool keep_first_pose_ = false;
  SurpriseCheck surprise_check_;
  TiltReference tilt_;  // the gravity reference's hold on roll and pitch
  std::optional<RangeCalibration> range_calibration_;  // config_.range_calibration
  std::optional<PreparedScan> held_;       // first scan with times, waiting for the motion
  std::optional<FrameEstimate> released_;  // held_ once finalised
};

}  // namespace socc::odom
