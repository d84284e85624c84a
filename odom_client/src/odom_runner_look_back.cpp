// OdomRunner with --own-frame, looking back: the robot's kept scans searched again in the shared
// map (another robot may since have mapped a place it passed), and a kept place found held until
// the newest place is searched near it (docs/relocalization.md "Own frame", "Look back").
#include <iostream>
#include <utility>

#include "socc/odom/odom_runner.hpp"

namespace socc::odom {

std::string OdomRunner::holdKeptPlace(const SearchOutcome& found) {
  // Merged at once, the robot's newest place would carry the own-frame drift since the kept
  // scan; where the shared map holds it too, a search near where the kept place puts it finds
  // it, and both places are kept (FrameBridge).
  kept_place_ = found;
  kept_place_checks_ = 0;
  return "found kept scan " + std::to_string(found.seq) +
         " in the shared map (looking back): searching near it for the newest place";
}

PoseHint OdomRunner::nearKeptPlace(const FrameEstimate& newest) const {
  // Where the kept place puts the newest scan, give or take the own-frame odometry's drift since
  // the kept scan (kKeptPlaceDrift of its path) on top of the usual hint radius.
  constexpr double kKeptPlaceDrift = 0.02;
  PoseHint near;
  near.position =
      (sharedFromOwn(*kept_place_->found.pose, kept_place_->own_pose) * newest.pose).translation();
  near.radius = config_.relocalize_hint_radius + kKeptPlaceDrift * ownPathSince(kept_place_->seq);
  return near;
}

double OdomRunner::ownPathSince(std::int64_t seq) const {
  double path = 0.0;
  for (std::size_t i = own_rows_begin_ + 1; i < trajectory_.poses.size(); ++i)
    if (trajectory_.seqs[i - 1] >= seq)
      path += (trajectory_.poses[i].translation() - trajectory_.poses[i - 1].translation()).norm();
  return path;
}

bool OdomRunner::launchLookBack() {
  std::optional<KeptPlaceSearch> next =
      own_sweep_->next(*own_, config_.deskew_reference_time, look_back_in_map_);
  if (!next) return false;
  startLookBack(std::move(*next));
  return true;
}

void OdomRunner::startLookBack(KeptPlaceSearch search) {
  // A new sweep starts from the oldest kept scan: the places the last one followed are stale.
  if (search.sweep_start || !own_look_back_) own_look_back_.emplace(config_, client_);
  const std::int64_t seq = search.stacked.seq;
  own_look_back_->start(std::move(search.stacked), search.scans, search.motion, std::nullopt, seq,
                        search.own_pose);
}

std::optional<SearchOutcome> OdomRunner::lookBackOnce() {
  // Nothing else to do: one whole sweep, a search after the other.
  if (!own_sweep_) return std::nullopt;
  own_sweep_->restart();
  look_back_in_map_ = false;
  std::cerr << "odom_client: the input ended in its own frame: looking back over its "
            << own_->keyframes().size() << " kept scans\n";
  for (bool first = true;; first = false) {
    std::optional<KeptPlaceSearch> next =
        own_sweep_->next(*own_, config_.deskew_reference_time, look_back_in_map_);
    if (!next || (next->sweep_start && !first)) return std::nullopt;  // none, or swept once
    startLookBack(std::move(*next));
    std::optional<SearchOutcome> done = ownSearchOutcome(true);
    if (done && done->found.pose) return done;
    if (done) std::cerr << "odom_client: " << verdictText(*done) << "\n";
  }
}

FrameBridge OdomRunner::bridgeTo(const SearchOutcome& kept_place, std::int64_t seq,
                                 const Eigen::Isometry3d& shared_T_own) const {
  std::vector<std::int64_t> seqs;
  std::vector<Eigen::Vector3d> positions;
  for (std::size_t i = own_rows_begin_; i < trajectory_.poses.size(); ++i) {
    seqs.push_back(trajectory_.seqs[i]);
    positions.push_back(trajectory_.poses[i].translation());
  }
  return FrameBridge(seqs, positions, kept_place.seq,
                     sharedFromOwn(*kept_place.found.pose, kept_place.own_pose), seq, shared_T_own);
}

}  // namespace socc::odom
