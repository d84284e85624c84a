#include "socc/odom/own_frame_map.hpp"

#include <algorithm>

namespace socc::odom {

OwnFrameMap::OwnFrameMap(OwnFrameLimits limits)
    : limits_(limits), keyframe_distance_(limits.keyframe_distance), recent_(limits.recent_scans) {}

void OwnFrameMap::add(const FrameEstimate& frame) {
  recent_.push(frame);
  if (!isKeyframe(frame.pose)) return;
  keyframes_.push_back({frame.seq, frame.utime, frame.pose,
                        thinnedCloud(frame.cloud, limits_.keyframe_spacing), frame.gravity});
  if (keyframes_.size() > std::max<std::size_t>(1, limits_.max_keyframes)) thin();
}

void OwnFrameMap::thin() {
  std::vector<OwnKeyframe> kept;
  for (std::size_t i = 0; i < keyframes_.size(); ++i)
    if (i % 2 == 0 || i + 1 == keyframes_.size()) kept.push_back(std::move(keyframes_[i]));
  dropped_ += keyframes_.size() - kept.size();
  keyframes_ = std::move(kept);
  keyframe_distance_ *= 2.0;
}

bool OwnFrameMap::isKeyframe(const Eigen::Isometry3d& pose) const {
  if (keyframes_.empty()) return true;
  const Eigen::Isometry3d step = keyframes_.back().pose.inverse() * pose;
  return step.translation().norm() >= keyframe_distance_ ||
         Eigen::AngleAxisd(step.linear()).angle() >= limits_.keyframe_angle;
}

std::size_t OwnFrameMap::keyframeBytes() const {
  std::size_t total = 0;
  for (const OwnKeyframe& k : keyframes_) total += cloudBytes(k.cloud) + sizeof(OwnKeyframe);
  return total;
}

Eigen::Isometry3d sharedFromOwn(const Eigen::Isometry3d& verified, const Eigen::Isometry3d& own) {
  return verified * own.inverse();
}

std::vector<OwnKeyframe> mergedKeyframes(const std::vector<OwnKeyframe>& keyframes,
                                         const OwnKeyframe& newest, const FrameBridge& bridge) {
  std::vector<OwnKeyframe> out = keyframes;
  if (out.empty() || out.back().seq < newest.seq) out.push_back(newest);
  for (OwnKeyframe& k : out) k.pose = bridge.at(k.seq) * k.pose;
  return out;
}

}  // namespace socc::odom
