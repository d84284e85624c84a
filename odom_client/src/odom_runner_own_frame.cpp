// OdomRunner with --own-frame: a robot that finds no pose in the shared map maps in its own frame
// and is merged into the shared one when its search finds the map (docs/relocalization.md "Own
// frame"). Nothing of it reaches the server before the merge.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <utility>

#include "socc/odom/odom_runner.hpp"
#include "socc/odom/service_map_access.hpp"
#include "socc/pose_conversion.hpp"

namespace socc::odom {
namespace {

std::string mergeText(const Eigen::Isometry3d& shared_T_own, const FrameBridge& bridge,
                      std::size_t keyframes, const OwnFrameMap& own) {
  constexpr double kMiB = 1024.0 * 1024.0;
  std::ostringstream out;
  out.precision(2);
  out << std::fixed << "merged into the shared map (own frame moved "
      << shared_T_own.translation().norm() << " m, "
      << Eigen::AngleAxisd(shared_T_own.linear()).angle() * 180.0 / M_PI << " deg; ";
  if (bridge.bridgedPath() > 0.0)
    out << "a drift of " << bridge.bridgedDrift() << " m bridged over " << bridge.bridgedPath()
        << " m of own-frame path; ";
  out << keyframes << " kept scans integrated; kept " << own.keyframeBytes() / kMiB
      << " MiB of keyframes and " << own.recentBytes() / kMiB << " MiB of recent scans)";
  return out.str();
}

// A kept scan's INTEGRATE, its pose in the frame of map instance epoch (or FOUND_MAP).
integrate_request_t keptScanRequest(const OwnKeyframe& keyframe, std::int64_t epoch) {
  integrate_request_t request = rpc::makeIntegrateRequest(
      keyframe.seq, keyframe.utime, keyframe.pose, keyframe.cloud, keyframe.gravity);
  request.map_epoch = epoch;
  return request;
}

}  // namespace

void OdomRunner::startOwnFrame(Odometry& odometry, const PreparedScan& scan) {
  // Identity at this scan; no free-space check against the shared map (not in its frame yet).
  odometry = Odometry(config_, Eigen::Isometry3d::Identity(), false);
  own_.emplace();
  own_rows_begin_ = trajectory_.poses.size();
  own_since_utime_ = scan.utime;
  own_search_.emplace(config_, client_);
  found_tried_ = false;
  if (config_.own_frame_look_back)
    own_sweep_.emplace(config_.relocalize_stack_scans, config_.own_frame_look_back_gap);
  std::cerr << "odom_client: mapping in its own frame while searching the shared map\n";
  // The server knows no pose of this robot yet (NOT_FOUND): the report is for SOCC/STATUS.
  sendStatus(robot_status_request_t::RELOCALIZING, "mapping in its own frame", scan.seq,
             scan.utime);
}

void OdomRunner::ownFrameScan(Odometry& odometry, const PreparedScan& scan,
                              std::chrono::steady_clock::time_point start) {
  FrameStats stats;
  stats.frame = scan.seq;
  stats.preprocess_ms = msSince(start);
  const LocalMap map = own_->target();
  stats.chunk_voxels = static_cast<std::int64_t>(map.size());
  const auto register_start = std::chrono::steady_clock::now();
  FrameEstimate estimate = odometry.registerFrame(scan, map);
  stats.register_ms = msSince(register_start);
  if (std::optional<FrameEstimate> first = odometry.takeReleasedFrame()) {
    FrameStats first_stats;
    first_stats.frame = first->seq;
    keepOwnFrame(*first, first_stats);
    log_->add(first_stats);
  }
  if (estimate.held) return;
  const bool kept = keepOwnFrame(estimate, stats);
  if (std::string verdict = followSearch(odometry, estimate, kept); !verdict.empty())
    stats.problem = std::move(verdict);
  stats.total_ms = msSince(start);
  log_->add(stats);
}

bool OdomRunner::keepOwnFrame(const FrameEstimate& frame, FrameStats& stats) {
  addHealth(frame, stats);
  stats.status = "own_frame";
  if (!frame.health.healthy()) stats.problem = "unhealthy: " + frame.health.problem;
  trajectory_.seqs.push_back(frame.seq);
  trajectory_.stamps.push_back(frame.utime * 1e-6);
  trajectory_.poses.push_back(frame.pose);
  if (!frame.health.healthy()) return false;  // not kept: the own map holds trusted scans only
  own_->add(frame);
  return true;
}

bool OdomRunner::ownSearchDue(std::int64_t utime) const {
  if (own_searched_utime_ < 0) return true;
  if ((utime - own_since_utime_) * 1e-6 <= config_.relocalize_timeout) return true;
  // Then rate-limited: each search costs the server a LOCALIZE (1e-3: scan stamps in us).
  return (utime - own_searched_utime_) * 1e-6 >= config_.own_frame_search_period - 1e-3;
}

std::string OdomRunner::followSearch(Odometry& odometry, const FrameEstimate& newest, bool kept) {
  // Only a trusted frame is where the odometry goes on in the shared map, and what is stacked.
  if (!kept) return {};
  if (options_.found_map && !found_tried_) {
    found_tried_ = true;  // once: a map founded by another robot is searched from then on
    if (foundSharedMap(odometry, newest)) return std::exchange(jump_, {});
  }
  std::optional<SearchOutcome> done = ownSearchOutcome(false);
  if (!done && !ownSearchRunning() && ownSearchDue(newest.utime)) {
    launchSearch(newest);
    // File input is not paced by a sensor: waiting keeps its searches one per due scan.
    if (!live_input_) done = ownSearchOutcome(true);
  }
  if (!done) return {};
  if (done->found.pose && done->looked_back) return holdKeptPlace(*done);
  if (!done->found.pose) {
    // A kept place found, the newest not (relocalize_confirm_scans + 1 searches near where the
    // kept place puts it): the robot is where nobody mapped yet, and the kept place places it.
    if (!kept_place_ || ++kept_place_checks_ <= config_.relocalize_confirm_scans)
      return verdictText(*done);
    mergeOwnFrame(odometry, {newest.seq, newest.utime, newest.pose, newest.cloud, newest.gravity},
                  *std::exchange(kept_place_, std::nullopt), std::nullopt);
  } else {
    mergeOwnFrame(odometry, {newest.seq, newest.utime, newest.pose, newest.cloud, newest.gravity},
                  *done, std::exchange(kept_place_, std::nullopt));
  }
  return std::exchange(jump_, {});  // this frame's row says it (not the next frame's)
}

std::string OdomRunner::verdictText(const SearchOutcome& done) const {
  const std::string what =
      done.looked_back ? "searching the shared map (kept scan " + std::to_string(done.seq) + ")"
                       : std::string("searching the shared map");
  return what + (kept_place_ ? " near the kept place found: " : ": ") + done.found.problem;
}

void OdomRunner::launchSearch(const FrameEstimate& newest) {
  own_searched_utime_ = newest.utime;
  if (kept_place_) {
    launchForward(newest, nearKeptPlace(newest));
    return;
  }
  // The first relocalize_timeout s search every scan for the robot's own place only (as
  // --relocalize would); then, with own_frame_look_back_live, every other search looks back.
  const bool looking_back = config_.own_frame_look_back_live && own_sweep_ &&
                            (newest.utime - own_since_utime_) * 1e-6 > config_.relocalize_timeout;
  if (looking_back && std::exchange(look_back_next_, false) && launchLookBack()) return;
  look_back_next_ = looking_back;
  launchForward(newest, hint_);
}

void OdomRunner::launchForward(const FrameEstimate& newest, const std::optional<PoseHint>& hint) {
  // The places followed since the last search move by the own-frame odometry in between.
  const Eigen::Isometry3d motion = own_searched_pose_.inverse() * newest.pose;
  own_searched_pose_ = newest.pose;
  const std::size_t count = static_cast<std::size_t>(config_.relocalize_stack_scans);
  own_search_->start(own_->stacked(count, config_.deskew_reference_time),
                     static_cast<int>(std::min(count, own_->frames())), motion, hint, newest.seq,
                     newest.pose);
}

bool OdomRunner::ownSearchRunning() const {
  return own_search_->running() || (own_look_back_ && own_look_back_->running());
}

std::optional<SearchOutcome> OdomRunner::ownSearchOutcome(bool wait) {
  std::optional<SearchOutcome> done = wait ? own_search_->wait() : own_search_->poll();
  if (done || !own_look_back_) return done;
  done = wait ? own_look_back_->wait() : own_look_back_->poll();
  if (!done) return done;
  done->looked_back = true;
  look_back_in_map_ = done->found.evidence >= config_.relocalize_min_fitness;
  return done;
}

void OdomRunner::finishOwnSearch(Odometry& odometry) {
  // The input ended while a search ran: its answer still merges what the robot kept.
  std::optional<SearchOutcome> done = ownSearchOutcome(true);
  if (done && done->found.pose && done->looked_back) kept_place_ = std::exchange(done, {});
  const bool newest_found = done && done->found.pose;
  if (!newest_found && !kept_place_) kept_place_ = lookBackOnce();
  if (own_->keyframes().empty()) return;
  if (newest_found)
    mergeOwnFrame(odometry, own_->keyframes().back(), *done, kept_place_);
  else if (kept_place_)
    mergeOwnFrame(odometry, own_->keyframes().back(), *kept_place_, std::nullopt);
}

void OdomRunner::mergeOwnFrame(Odometry& odometry, const OwnKeyframe& newest,
                               const SearchOutcome& search,
                               const std::optional<SearchOutcome>& kept_place) {
  const Relocalization& found = search.found;
  std::cerr << "odom_client: found the shared map at frame " << search.seq
            << (search.looked_back ? " (a kept scan, looking back; answered" : " (answered")
            << " at frame " << newest.seq << "; confirmed on " << found.confirmed
            << " searches; explains " << static_cast<int>(found.fitness * 100) << " % of the last "
            << found.stacked << " scans, " << static_cast<int>(found.free * 100)
            << " % in free space; next place " << static_cast<int>(found.runner_up * 100)
            << " % net)\n";
  const Eigen::Isometry3d shared_T_own = sharedFromOwn(*found.pose, search.own_pose);
  const FrameBridge bridge = kept_place && kept_place->seq < search.seq
                                 ? bridgeTo(*kept_place, search.seq, shared_T_own)
                                 : FrameBridge(shared_T_own);
  joinSharedMap(odometry, newest, bridge, shared_T_own, found.map_epoch);
  ++relocalizations_;
}

bool OdomRunner::foundSharedMap(Odometry& odometry, const FrameEstimate& newest) {
  // The first kept scan founds the map at its own-frame pose: the own frame is the map frame.
  const OwnKeyframe& first = own_->keyframes().front();
  const auto reply = client_.integrate(keptScanRequest(first, integrate_request_t::FOUND_MAP));
  if (!reply.ok()) {
    if (reply.error.status != reply_header_t::FAILED_PRECONDITION)
      throw std::runtime_error(callError("INTEGRATE", reply.error, reply.attempts));
    std::cerr << "odom_client: not founding the shared map: " << reply.error.message << "\n";
    return false;
  }
  std::cerr << "odom_client: founded the shared map at frame " << first.seq
            << " (it was empty): its own frame is the map frame\n";
  const Eigen::Isometry3d same = Eigen::Isometry3d::Identity();
  joinSharedMap(odometry, {newest.seq, newest.utime, newest.pose, newest.cloud, newest.gravity},
                FrameBridge(same), same, reply.reply->map_epoch);
  return true;
}

void OdomRunner::joinSharedMap(Odometry& odometry, const OwnKeyframe& newest,
                               const FrameBridge& bridge, const Eigen::Isometry3d& shared_T_own,
                               std::int64_t epoch) {
  const std::vector<OwnKeyframe> kept = mergedKeyframes(own_->keyframes(), newest, bridge);
  // The own-frame stretch reaches the shared map in order, before the robot's next frame: the
  // server sees a robot's first integration and then plausible steps (a founder's first kept
  // scan is in already: sent again, it is acknowledged as a duplicate).
  for (const OwnKeyframe& k : kept) integrateKept(k, epoch);
  for (std::size_t i = own_rows_begin_; i < trajectory_.poses.size(); ++i)
    trajectory_.poses[i] = bridge.at(trajectory_.seqs[i]) * trajectory_.poses[i];
  odometry.moveFrame(shared_T_own);  // as a map correction, the map's up turned too
  watch(odometry);
  jump_ = mergeText(shared_T_own, bridge, kept.size(), *own_);
  std::cerr << "odom_client: " << jump_ << "\n";
  if (own_->droppedKeyframes() > 0)
    std::cerr << "odom_client: the kept scans were thinned to one every "
              << own_->keyframeDistance() << " m (max_keyframes; " << own_->droppedKeyframes()
              << " left out)\n";
  tracking_ = TrackingMonitor(config_.max_unhealthy_frames);
  last_good_ = shared_T_own * newest.pose;
  sendStatus(robot_status_request_t::TRACKING, "merged into the shared map", newest.seq,
             newest.utime);
  own_.reset();
  own_search_.reset();
  own_look_back_.reset();
  own_sweep_.reset();
  kept_place_.reset();
  localized_ = true;
}

void OdomRunner::integrateKept(const OwnKeyframe& keyframe, std::int64_t epoch) {
  const auto reply = client_.integrate(keptScanRequest(keyframe, epoch));
  if (reply.ok()) return;
  if (reply.error.status == reply_header_t::FAILED_PRECONDITION) {  // judged implausible
    std::cerr << "odom_client: warning: the server refused kept scan " << keyframe.seq << ": "
              << reply.error.message << "\n";
    return;
  }
  throw std::runtime_error(callError("INTEGRATE", reply.error, reply.attempts));
}

}  // namespace socc::odom
