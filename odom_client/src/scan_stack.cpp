#include "socc/odom/scan_stack.hpp"

#include <utility>

#include "socc/odom/scan_map.hpp"
#include "socc/odom/voxel_downsampling.hpp"

namespace socc::odom {
namespace {

// The map server's voxel size (MapConfig): the stacked scans are a target like its chunks.
constexpr double kTargetVoxel = 0.5;  // [m]
// Each stacked scan is kept thinned to this spacing: the registrations downsample coarser anyway,
// and a near object's thousands of returns would otherwise dominate the cost of every candidate.
constexpr double kKeptSpacing = 0.1;  // [m]

LabeledCloud thinned(const LabeledCloud& cloud) {
  std::array<double, kNumClasses> same_size{};
  same_size.fill(1.0);
  LabeledCloud geometry;
  geometry.points = cloud.points;
  geometry.labels = cloud.labels;  // the registration weighs labels: keep them, drop times
  return semanticVoxelDownsample(geometry, kKeptSpacing, same_size);
}

}  // namespace

ScanStack::ScanStack(const OdomConfig& config, std::size_t max_scans)
    : config_(config), max_scans_(std::max<std::size_t>(1, max_scans)) {}

void ScanStack::restart() {
  odometry_.emplace(config_, Eigen::Isometry3d::Identity());
  frames_.clear();
  last_motion_.setIdentity();
}

bool ScanStack::add(const PreparedScan& scan) {
  restarted_ = false;
  if (!odometry_) restart();
  FrameEstimate estimate = odometry_->registerFrame(scan, target());
  if (std::optional<FrameEstimate> first = odometry_->takeReleasedFrame()) push(std::move(*first));
  if (estimate.held) return true;
  if (!estimate.health.healthy()) {
    restart();
    restarted_ = true;
    FrameEstimate fresh = odometry_->registerFrame(scan, LocalMap());
    if (!fresh.held) push(std::move(fresh));
    return false;
  }
  push(std::move(estimate));
  return true;
}

void ScanStack::push(FrameEstimate estimate) {
  last_motion_ = frames_.empty() ? Eigen::Isometry3d::Identity()
                                 : frames_.back().pose.inverse() * estimate.pose;
  frames_.push_back({thinned(estimate.cloud), estimate.pose, estimate.seq, estimate.utime});
  while (frames_.size() > max_scans_) frames_.pop_front();
}

LocalMap ScanStack::target() const {
  LabeledCloud all;
  for (const Frame& f : frames_) {
    const LabeledCloud moved = transformed(f.cloud, f.pose);
    all.points.insert(all.points.end(), moved.points.begin(), moved.points.end());
    all.labels.insert(all.labels.end(), moved.labels.begin(), moved.labels.end());
  }
  return buildScanMap(all, kTargetVoxel);
}

PreparedScan ScanStack::cloud() const {
  PreparedScan out;
  if (frames_.empty()) return out;
  const Frame& newest = frames_.back();
  out.seq = newest.seq;
  out.utime = newest.utime;
  out.mid_time = config_.deskew_reference_time;  // the stacked points are at the reference time
  const Eigen::Isometry3d newest_inv = newest.pose.inverse();
  for (const Frame& f : frames_) {
    const LabeledCloud moved = transformed(f.cloud, newest_inv * f.pose);
    out.cloud.points.insert(out.cloud.points.end(), moved.points.begin(), moved.points.end());
    out.cloud.labels.insert(out.cloud.labels.end(), moved.labels.begin(), moved.labels.end());
  }
  return out;
}

}  // namespace socc::odom
