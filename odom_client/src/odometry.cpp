#include "socc/odom/odometry.hpp"

#include <stdexcept>

#include "socc/odom/deskew.hpp"
#include "socc/odom/preprocessing.hpp"
#include "socc/odom/se3.hpp"

namespace socc::odom {

Odometry::Odometry(const OdomConfig& config, const Eigen::Isometry3d& initial_pose,
                   bool initial_pose_known)
    : config_(config),
      class_factor_(classFactors(config)),
      params_{config.planarity_threshold, config.gamma, config.w_lower, config.max_iterations,
              config.convergence},
      threshold_(config.initial_threshold, config.min_motion, config.max_range),
      voxel_size_(config.initial_voxel_size, config.min_voxel_size, config.max_voxel_size,
                  config.target_points),
      pose_(initial_pose),
      keep_first_pose_(initial_pose_known && !config.refine_initial_pose) {}

PreparedScan Odometry::prepare(const LabeledCloud& raw, double frame_period) {
  if (const std::string problem = checkCloud(raw); !problem.empty())
    throw std::invalid_argument("bad scan: " + problem);
  PreparedScan out;
  out.full = rangeFilter(raw, config_.min_range, config_.max_range);
  if (!config_.use_semantics) dropLabels(out.full);
  if (config_.deskew && out.full.hasTimes())
    out.full = deskew(out.full, velocity_, frame_period, config_.deskew_reference_time);
  out.full.times.clear();  // deskewed: the points now all refer to the reference time

  out.voxel_size = voxel_size_.size();
  out.downsampled = semanticVoxelDownsample(out.full, out.voxel_size, class_factor_);
  if (voxel_size_.farOff(out.downsampled.size())) {
    // e.g. the first frame or a sudden change of scene: redo once with the corrected size.
    voxel_size_.update(out.downsampled.size());
    out.voxel_size = voxel_size_.size();
    out.downsampled = semanticVoxelDownsample(out.full, out.voxel_size, class_factor_);
  }
  voxel_size_.update(out.downsampled.size());
  return out;
}

Eigen::Isometry3d Odometry::predictedPose() const {
  return pose_ * velocity_;
}

FrameEstimate Odometry::registerFrame(const PreparedScan& scan, const LocalMap& map) {
  const Eigen::Isometry3d prediction = predictedPose();
  FrameEstimate out;
  out.sigma = threshold_.sigma();
  out.pose = prediction;
  const bool keep = keep_first_pose_ && !has_motion_model_;
  if (!keep && map.size() >= static_cast<std::size_t>(std::max(config_.min_map_points, 1))) {
    out.registration = registerScan(scan.downsampled, map, prediction, out.sigma, params_);
    if (!threshold_.calibrated()) refine(scan, map, out);
    out.pose = orthonormalized(out.registration.pose);
    out.registered = true;
    if (has_motion_model_) threshold_.update(prediction.inverse() * out.pose);
  }
  has_motion_model_ = true;
  velocity_ = orthonormalized(pose_.inverse() * out.pose);
  pose_ = out.pose;
  return out;
}

void Odometry::refine(const PreparedScan& scan, const LocalMap& map, FrameEstimate& out) const {
  // The initial threshold is wide so that it catches an unknown motion (or a rough initial pose
  // in a map other robots built): its kernel also gives weight to wrong correspondences, which
  // leaves the pose biased by centimetres. Halving sigma from the coarse result removes them;
  // a pose that enters another robot's map this way would otherwise shift that map for everyone.
  if (config_.refine_threshold <= 0.0) return;  // off
  for (double sigma = out.sigma / 2.0; sigma >= config_.refine_threshold; sigma /= 2.0) {
    const int iterations = out.registration.iterations;
    out.registration = registerScan(scan.downsampled, map, out.registration.pose, sigma, params_);
    out.registration.iterations += iterations;
  }
}

void Odometry::reset(const Eigen::Isometry3d& pose) {
  pose_ = pose;
  velocity_ = Eigen::Isometry3d::Identity();
  has_motion_model_ = false;
  keep_first_pose_ = false;  // e.g. the last pose the server holds: the next scan is elsewhere
  threshold_.reset();
}

}  // namespace socc::odom
