#pragma once
// Parameters of the odometry client (YAML: see odom_client/config/default.yaml).
// Defaults are the SOCC-ICP paper's hyperparameters for driving data (KITTI).
#include <array>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "socc/labels.hpp"

namespace socc::odom {

struct OdomConfig {
  // Preprocessing.
  double min_range = 5.0;    // [m] closer points are dropped (ego vehicle)
  double max_range = 100.0;  // [m]
  bool deskew = true;        // when per-point times exist (or azimuth_times)
  // [deg] added to every point's elevation: a sensor's common vertical-angle error (KITTI's
  // HDL-64: 0.205, config/kitti.yaml). 0: the points as given.
  double vertical_angle_correction_deg = 0.0;
  double frame_period = 0.1;           // [s] used when scans carry no timestamps
  double deskew_reference_time = 0.0;  // [s, relative to scan time] the instant the pose refers to
  int deskew_iterations = 3;  // deskew + register passes per frame with the frame's own motion
  // Continuous-time registration (SweepTwistPrior): how far the twist within a sweep may be from
  // the one measured between the last two poses (standard deviations; 0 holds that part at the
  // measured twist; both 0: off). docs/robustness.md says how they were chosen.
  double sweep_twist_sigma_linear = 0.05;    // [m/s]
  double sweep_twist_sigma_angular = 0.005;  // [rad/s]
  // Per-laser range offsets and scales fitted from the lasers' disagreement on the map's walls
  // (range_calibration.hpp).
  bool range_calibration = true;

  // Per-point times of scans that carry none, derived from each point's azimuth (a spinning
  // sensor, e.g. KITTI): the sweep starts at azimuth_start_deg and turns one revolution per
  // frame_period; the scan's timestamp lies at scan_time_in_sweep (0 start, 0.5 middle, 1 end).
  bool azimuth_times = false;
  double azimuth_start_deg = 180.0;  // [deg] 180: the sweep starts facing backwards
  bool azimuth_clockwise = true;     // seen from above (azimuth decreasing)
  double scan_time_in_sweep = 0.0;

  // Per-frame health (docs/robustness.md): an unhealthy frame is not integrated; after
  // max_unhealthy_frames of them in a row the robot declares itself lost and relocalizes. The
  // kinematic limits only mark a surprise (frame_health.hpp).
  double min_inlier_fraction = 0.2;  // correspondences / registered points
  double max_residual_ratio = 1.0;   // RMS residual / sigma
  double min_constraint = 40.0;  // planar pairs pinning the weakest direction; below: degenerate
  // A degenerate frame is registered again with the motion model's prediction along its weakest
  // direction as evidence worth min_constraint planar pairs: the odometry coasts along it
  // instead of sliding on the scan's noise.
  bool hold_degenerate_direction = true;
  double max_linear_speed = 40.0;           // [m/s]
  double max_angular_speed = 360.0;         // [deg/s]
  double max_linear_acceleration = 20.0;    // [m/s^2]
  double max_angular_acceleration = 720.0;  // [deg/s^2]
  int max_unhealthy_frames = 5;

  // Semantic-aware adaptive voxel downsampling: v_c = alpha_c * v_adapt.
  int target_points = 2500;         // v_adapt follows the previous frame's count to keep ~this many
  double initial_voxel_size = 1.0;  // [m]
  double min_voxel_size = 0.2;      // [m]
  double max_voxel_size = 4.0;      // [m]
  double alpha_human = 0.0;         // person, bicyclist, motorcyclist (0 = dropped)
  double alpha_pole_sign = 0.75;    // pole, traffic-sign
  double alpha_ground = 0.8;        // road, parking, sidewalk, terrain
  double alpha_default = 1.0;       // every other class, and unlabeled
  bool use_semantics = true;        // false: every label is treated as 0 (unlabeled)
  bool use_gravity = true;  // false: the source's gravity reference is not sent (--no-gravity)
  // [deg / sqrt(s)] how fast the odometry's tilt drifts without a gravity reference: the
  // reference's weight against the registration (tilt_reference.hpp); 0: the reference is only
  // sent, the odometry does not use it.
  double gravity_tilt_walk_deg = 0.03;
  // A recording's IMU as the gravity reference (--imu-topic): the IMU frame's orientation in
  // the sensor frame, as yaw about z, then pitch about y, then roll about x [deg] (sensor_R_imu =
  // Rz(yaw) Ry(pitch) Rx(roll)); NaN: not stated, and --imu-topic refuses to guess it (a wrong
  // mounting turns the vehicle's pitch into roll and pulls the tilt with a confident sigma). Then
  // the 1-sigma of its attitude's roll and pitch [deg]; 0: the messages' orientation_covariance,
  // or 0.5 deg where they state none.
  double imu_roll_deg = std::numeric_limits<double>::quiet_NaN();
  double imu_pitch_deg = std::numeric_limits<double>::quiet_NaN();
  double imu_yaw_deg = std::numeric_limits<double>::quiet_NaN();
  double imu_attitude_sigma_deg = 0.0;

  // KISS-ICP adaptive threshold.
  double initial_threshold = 2.0;  // [m] sigma before any motion was observed
  double min_motion = 0.1;         // [m] corrections below this do not update sigma
  double refine_threshold = 0.25;  // [m] coarse-to-fine floor while sigma is initial; 0 = off

  // Joining a map: register the first scan even at a given (--initial-pose) pose.
  bool refine_initial_pose = false;

  // Map chunk around the predicted pose.
  double chunk_radius = 125.0;       // [m]
  double occupancy_threshold = 0.5;  // voxels with p_occ >= this are correspondence candidates
  int min_map_points = 100;  // fewer occupied voxels: keep the prediction (e.g. first frame)
  // Register each frame against the chunk fetched after the frame before last plus the last
  // frame's own voxels, while the server integrates (map_pipeline.hpp); false: wait for the
  // server to integrate the last frame and fetch the chunk after it.
  bool pipelined_map = true;
  // ... and fetch those chunks as deltas on the last one (chunk_cache.hpp).
  bool delta_chunks = true;
  // ... a chunk with every chunk_interval-th Integrate: the frames in between register against
  // the last chunk plus the frames integrated since, merged into it as the server merges them
  // (1: a chunk every frame). The chunk then brings what the client cannot know: other robots'
  // points and cleared space, at most chunk_interval frames late.
  int chunk_interval = 8;

  // Registration.
  double planarity_threshold = 0.1;  // tau < this (and n >= 5) => point-to-plane
  bool point_to_plane = true;        // false: point-to-point only (the demo's baseline)
  bool sparse_voxel_pairs = true;    // pairs with voxels of < 5 points (see RegistrationParams)
  // ... taken along the scan's own surface normal where it has one (scan_normals.hpp), else to
  // the voxel's first point.
  bool sparse_pairs_along_scan_normal = true;
  // ... and where the scan point has none, to the voxel's first point (RegistrationParams).
  bool sparse_point_pairs = false;
  double gamma = 1.5;     // w_occ = p_occ^gamma
  double w_lower = 0.25;  // semantic weight of non-matching labels
  int max_iterations = 100;
  double convergence = 1e-4;  // ||dx|| below this stops the iterations

  // Relocalization (--relocalize, and recovery after LOST; docs/relocalization.md): the server's
  // candidate poses are each verified by registration; one is accepted only when it is healthy,
  // puts at most relocalize_max_free of the scan into the map's free space, and its evidence
  // (fitness minus free share) is at least relocalize_min_fitness and exceeds any other such
  // place's by relocalize_margin on average over at least relocalize_confirm_scans consecutive
  // scans, by relocalize_scan_lead on each of them (the last
  // relocalize_stack_scans scans stacked by the robot's own odometry and matched as one).
  int relocalize_candidates = 5;        // candidates verified per scan
  double relocalize_min_fitness = 0.5;  // share within 0.5 m of the map, net of the free share
  double relocalize_max_free = 0.2;     // share of (observed) scan points in the map's free space
  double relocalize_margin = 0.1;       // over the next distinct candidate's evidence
  double relocalize_scan_lead = 0.08;   // ... at least this much on each confirming scan
  double relocalize_timeout = 10.0;     // [s of scan time] without success: exit 4 (or 3: lost)
  double relocalize_voxel_size = 0.5;   // [m] the scan is downsampled to this for LOCALIZE
  // [m] --resume --relocalize, recovery: around the last pose
  double relocalize_hint_radius = 30.0;
  int relocalize_stack_scans = 5;    // scans accumulated by odometry into one matched cloud
  int relocalize_confirm_scans = 2;  // consecutive scans a place must lead before it is accepted
  // --own-frame: after relocalize_timeout (searches on every scan) the shared map is searched
  // once per this much scan time [s]: each search costs the server a LOCALIZE.
  double own_frame_search_period = 0.5;
  // --own-frame: at the end of the input a robot never merged looks back over its kept scans once
  // (KeptPlaceSweep: another robot may since have mapped a place it passed); with
  // own_frame_look_back_live also during the run, every other search after relocalize_timeout
  // (off: on the KITTI-00 shape it delayed the merge, docs/relocalization.md "Look back"). Pairs
  // of windows of relocalize_stack_scans kept scans, own_frame_look_back_gap [m] of path apart.
  bool own_frame_look_back = true;
  bool own_frame_look_back_live = false;
  double own_frame_look_back_gap = 40.0;

  // Map service.
  int timeout_ms = 2000;  // per attempt
  int max_attempts = 5;
};

/// alpha_c per class id (0..K) from the config; all 1.0 when semantics are off.
std::array<double, kNumClasses> classFactors(const OdomConfig& cfg);

/// Loads a YAML file (flat keys named like the fields above). Unknown keys, wrong types and
/// invalid values throw std::runtime_error naming the file and the key; missing keys keep defaults.
OdomConfig loadOdomConfig(const std::filesystem::path& file);
/// Layers several files over the defaults in order: a key of a later file overrides the same key
/// of an earlier one (e.g. a sensor's config/kitti.yaml, then a method's config/baseline.yaml).
/// The result is validated once, after the last file.
OdomConfig loadOdomConfig(const std::vector<std::filesystem::path>& files);
/// Empty when cfg is valid, otherwise the first problem found.
std::string validate(const OdomConfig& cfg);

}  // namespace socc::odom
