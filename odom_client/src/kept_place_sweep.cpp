#include "socc/odom/kept_place_sweep.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "socc/odom/posed_frames.hpp"

namespace socc::odom {
namespace {

/// Index of the first keyframe with seq >= seq.
std::size_t firstFrom(const std::vector<OwnKeyframe>& keyframes, std::int64_t seq) {
  return static_cast<std::size_t>(
      std::lower_bound(keyframes.begin(), keyframes.end(), seq,
                       [](const OwnKeyframe& k, std::int64_t s) { return k.seq < s; }) -
      keyframes.begin());
}

/// The first keyframe at least gap metres of path after keyframes[from] (size() if none).
std::size_t afterPath(const std::vector<OwnKeyframe>& keyframes, std::size_t from, double gap) {
  double path = 0.0;
  std::size_t i = from;
  while (i + 1 < keyframes.size() && path < gap) {
    path += (keyframes[i + 1].pose.translation() - keyframes[i].pose.translation()).norm();
    ++i;
  }
  return path < gap ? keyframes.size() : i;
}

}  // namespace

KeptPlaceSweep::KeptPlaceSweep(int stack_scans, double gap) : stack_scans_(stack_scans), gap_(gap) {
  if (stack_scans < 1 || !(gap >= 0.0))
    throw std::invalid_argument("KeptPlaceSweep: stack_scans >= 1 and gap >= 0 required");
}

void KeptPlaceSweep::restart() {
  last_seq_.reset();
  last_pose_.reset();
  run_ = 0;
}

std::optional<KeptPlaceSearch> KeptPlaceSweep::next(const OwnFrameMap& own, double reference_time,
                                                    bool in_map) {
  const std::vector<OwnKeyframe>& kept = own.keyframes();
  const auto window = static_cast<std::size_t>(stack_scans_);
  // The newest window is the forward search's: a sweep ends before it.
  const std::size_t end = kept.size() < window ? 0 : kept.size() - window;
  std::size_t first = 0;
  if (last_seq_) {
    // After a pair, gap metres are skipped, unless the last window's place is in the map.
    const std::size_t after = firstFrom(kept, *last_seq_ + 1);
    const bool skip = run_ >= 2 && !in_map;
    first = skip ? afterPath(kept, after, gap_) : after;
    if (skip) run_ = 0;
  }
  if (first + window > end) {
    if (!last_seq_) return std::nullopt;  // too few kept scans for a sweep yet
    restart();
    return next(own, reference_time);
  }
  const std::size_t newest = first + window - 1;
  KeptPlaceSearch search;
  search.sweep_start = !last_pose_;
  search.own_pose = kept[newest].pose;
  search.motion = last_pose_ ? last_pose_->inverse() * search.own_pose : search.motion;
  search.scans = stack_scans_;
  search.stacked.seq = kept[newest].seq;
  search.stacked.utime = kept[newest].utime;
  search.stacked.mid_time = reference_time;
  const Eigen::Isometry3d newest_inv = search.own_pose.inverse();
  for (std::size_t i = first; i <= newest; ++i)
    appendMoved(kept[i].cloud, newest_inv * kept[i].pose, search.stacked.cloud);
  last_seq_ = search.stacked.seq;
  last_pose_ = search.own_pose;
  ++run_;
  return search;
}

}  // namespace socc::odom
