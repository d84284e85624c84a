#pragma once
// KITTI odometry benchmark metrics, following the definition of the KITTI devkit
// (evaluate_odometry.cpp): for every first frame i (every `step` frames) and every sub-sequence
// length L, the last frame j is the first frame whose ground-truth distance along the path
// exceeds dist(i) + L. The segment error is E = (est_i^-1 est_j)^-1 (gt_i^-1 gt_j);
// t_err = |trans(E)| / L and r_err = angle(E) / L. Results are averaged over all segments.
#include <cstddef>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc::eval {

struct KittiSegmentError {
  std::size_t first_frame = 0;
  std::size_t last_frame = 0;
  double length = 0.0;  // [m]
  double t_err = 0.0;   // [m/m]
  double r_err = 0.0;   // [rad/m]
};

struct KittiLengthError {
  double length = 0.0;       // [m]
  std::size_t segments = 0;  // 0: the trajectory is shorter than this length
  double t_err_percent = 0.0;
  double r_err_deg_per_100m = 0.0;
};

struct KittiMetrics {
  std::vector<KittiSegmentError> segments;
  std::vector<KittiLengthError> per_length;
  double t_err_percent = 0.0;       // mean over all segments, in %
  double r_err_deg_per_100m = 0.0;  // mean over all segments, in deg/100 m
  bool valid() const { return !segments.empty(); }
};

/// Mean errors of the segments whose speed is within kittiSpeedWindow of a bin centre.
struct KittiSpeedError {
  double speed = 0.0;  // bin centre [m/s]
  std::size_t segments = 0;
  double t_err_percent = 0.0;
  double r_err_deg_per_100m = 0.0;
};

std::vector<double> kittiDefaultLengths();  // 100, 200, ..., 800 m

/// Cumulative ground-truth path length at every frame (dist[0] = 0).
std::vector<double> trajectoryDistances(const Poses& poses);

/// Rotation angle of a pose in [0, pi]. Equal to the devkit's acos((trace - 1) / 2) for a
/// rotation, but computed as atan2(|vee(R - R^T)| / 2, (trace - 1) / 2): acos amplifies the tiny
/// non-orthonormality of text-file poses (angle ~ sqrt of the trace defect) near zero.
/// Poses are assumed rigid (loadTrajectory orthonormalises them).
double rotationAngle(const Eigen::Isometry3d& pose);

/// The devkit's error-vs-speed: a segment's speed is length / (frame_period * frames) with
/// frames = last - first + 1 (the devkit's 0.1 s per frame by default); bins centred at
/// 2, 4, ..., 24 m/s take the segments within +-2 m/s (overlapping, as the devkit). Bins
/// without segments are left out.
std::vector<KittiSpeedError> kittiErrorsBySpeed(const KittiMetrics& metrics,
                                                double frame_period = 0.1);

/// gt and est must have the same size (std::invalid_argument otherwise); lengths must be > 0.
KittiMetrics computeKittiMetrics(const Poses& gt, const Poses& est,
                                 const std::vector<double>& lengths = kittiDefaultLengths(),
                                 std::size_t step = 10);

}  // namespace socc::eval
