#include "socc/odom/odometry.hpp"

#include <stdexcept>

#include "socc/odom/deskew.hpp"
#include "socc/odom/preprocessing.hpp"
#include "socc/odom/se3.hpp"

namespace socc::odom {

Odometry::Odometry(const OdomConfig& config, const Eigen::Isometry3d& initial_pose)
    : config_(config),
      class_factor_(classFactors(config)),
      params_{config.planarity_threshold, config.gamma, config.w_lower, config.max_iterations,
              config.convergence},
      threshold_(config.initial_threshold, config.min_motion, config.max_range),
      voxel_size_(config.initial_voxel_size, config.min_voxel_size, config.max_voxel_size,
                  config.target_points),
      pose_(initial_pose) {}

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
  if (map.size() >= static_cast<std::size_t>(std::max(config_.min_map_points, 1))) {
    out.registration = registerScan(scan.downsampled, map, prediction, out.sigma, params_);
    out.pose = orthonormalized(out.registration.pose);
    out.registered = true;
    if (has_motion_model_) threshold_.update(prediction.inverse() * out.pose);
  }
  has_motion_model_ = true;
  velocity_ = orthonormalized(pose_.inverse() * out.pose);
  pose_ = out.pose;
  return out;
}

void Odometry::reset(const Eigen::Isometry3d& pose) {
  pose_ = pose;
  velocity_ = Eigen::Isometry3d::Identity();
  has_motion_model_ = false;
  threshold_.reset();
}

}  // namespace socc::odom
