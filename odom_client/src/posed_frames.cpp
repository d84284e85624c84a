#include "socc/odom/posed_frames.hpp"

#include <algorithm>
#include <array>

#include "socc/odom/voxel_downsampling.hpp"

namespace socc::odom {
namespace {

// The map server's voxel size (MapConfig): the kept frames are a target like its chunks.
constexpr double kTargetVoxel = 0.5;  // [m]
// Each kept scan is thinned to this spacing: the registrations downsample coarser anyway, and a
// near object's thousands of returns would otherwise dominate the cost of every candidate.
constexpr double kKeptSpacing = 0.1;  // [m]

}  // namespace

LabeledCloud thinnedCloud(const LabeledCloud& cloud, double spacing) {
  std::array<double, kNumClasses> same_size{};
  same_size.fill(1.0);
  LabeledCloud geometry;
  geometry.points = cloud.points;
  geometry.labels = cloud.labels;  // the registration weighs labels: keep them, drop times
  return semanticVoxelDownsample(geometry, spacing, same_size);
}

void appendMoved(const LabeledCloud& cloud, const Eigen::Isometry3d& pose, LabeledCloud& out) {
  const LabeledCloud moved = transformed(cloud, pose);
  out.points.insert(out.points.end(), moved.points.begin(), moved.points.end());
  out.labels.insert(out.labels.end(), moved.labels.begin(), moved.labels.end());
}

std::size_t cloudBytes(const LabeledCloud& cloud) {
  return cloud.points.capacity() * sizeof(cloud.points[0]) +
         cloud.labels.capacity() * sizeof(std::uint8_t) + cloud.times.capacity() * sizeof(float);
}

PosedFrames::PosedFrames(std::size_t max_frames)
    : max_frames_(std::max<std::size_t>(1, max_frames)) {}

void PosedFrames::push(const FrameEstimate& frame) {
  last_motion_ =
      frames_.empty() ? Eigen::Isometry3d::Identity() : frames_.back().pose.inverse() * frame.pose;
  LabeledCloud cloud = thinnedCloud(frame.cloud, kKeptSpacing);
  std::vector<CloudVoxel> voxels = cloudVoxels(cloud, frame.pose, kTargetVoxel);
  voxels.shrink_to_fit();  // reserved for a voxel every few points; kept for 10 frames
  frames_.push_back({std::move(cloud), frame.pose, frame.seq, frame.utime, std::move(voxels)});
  while (frames_.size() > max_frames_) frames_.pop_front();
}

void PosedFrames::clear() {
  frames_.clear();
  last_motion_.setIdentity();
}

Eigen::Isometry3d PosedFrames::newestPose() const {
  return frames_.empty() ? Eigen::Isometry3d::Identity() : frames_.back().pose;
}

LocalMap PosedFrames::target() const {
  std::vector<const std::vector<CloudVoxel>*> parts;
  for (const Frame& f : frames_) parts.push_back(&f.voxels);
  return buildVoxelMap(mergedVoxels(parts));
}

PreparedScan PosedFrames::stacked(std::size_t count, double reference_time) const {
  PreparedScan out;
  if (frames_.empty()) return out;
  const Frame& newest = frames_.back();
  out.seq = newest.seq;
  out.utime = newest.utime;
  out.mid_time = reference_time;
  const Eigen::Isometry3d newest_inv = newest.pose.inverse();
  const std::size_t first = frames_.size() - std::min(count, frames_.size());
  for (std::size_t i = first; i < frames_.size(); ++i)
    appendMoved(frames_[i].cloud, newest_inv * frames_[i].pose, out.cloud);
  return out;
}

std::size_t PosedFrames::bytes() const {
  std::size_t total = 0;
  for (const Frame& f : frames_)
    total += cloudBytes(f.cloud) + f.voxels.capacity() * sizeof(CloudVoxel);
  return total;
}

}  // namespace socc::odom
