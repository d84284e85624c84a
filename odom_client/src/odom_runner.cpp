#include "socc/odom/odom_runner.hpp"

#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "socc/odom/local_map.hpp"
#include "socc/odom/scan_preparer.hpp"
#include "socc/odom/service_map_access.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/progress_bar.hpp"

namespace socc::odom {
namespace {

using Clock = std::chrono::steady_clock;

// A frame's free-space check sends at most this many of its points (downsampled).
constexpr std::size_t kMaxCheckPoints = 20'000;

std::string statusOf(const FrameEstimate& e, TrackingState state) {
  if (state == TrackingState::kLost) return "lost";
  if (!e.health.healthy()) return "unhealthy";
  if (e.retried) return "retried";
  return e.health.degenerate ? "degenerate" : "ok";
}

std::string progressText(const FrameStats& stats, TrackingState state) {
  std::ostringstream out;
  out.precision(1);
  out << std::fixed << "register " << stats.register_ms << " ms, " << stats.chunk_voxels
      << " voxels, " << trackingStateName(state);
  return out.str();
}

}  // namespace

void addHealth(const FrameEstimate& e, FrameStats& stats) {
  stats.planar = e.registration.planar;
  stats.non_planar = e.registration.non_planar;
  stats.alpha = e.registration.alpha;
  stats.iterations = e.registration.iterations;
  stats.sigma = e.sigma;
  stats.points = static_cast<std::int64_t>(e.cloud.size());
  stats.downsampled_points = static_cast<std::int64_t>(e.registered_points);
  stats.deskew_passes = e.deskew_passes;
  stats.problem = e.health.problem;
  stats.surprise = e.health.surprise;
  stats.inlier_fraction = e.health.inlier_fraction;
  stats.residual_ratio = e.health.residual_ratio;
  stats.weakest_constraint = e.health.weakest_constraint;
  stats.speed = e.health.linear_speed;
}

OdomRunner::OdomRunner(const OdomConfig& config, rpc::MapClient& client, RunOptions options)
    : config_(config),
      client_(client),
      options_(options),
      tracking_(config.max_unhealthy_frames),
      localized_(!options.relocalize || options.initial_pose_known),
      hint_(options.hint) {
  if (options_.initial_pose_known) options_.own_frame = false;  // it is in the shared frame
}

void OdomRunner::run(ScanSource& source, FrameLog& log) {
  log_ = &log;
  live_input_ = source.live();
  pipeline_.emplace(client_, config_, log);
  Odometry odometry(config_, options_.initial_pose, options_.initial_pose_known);
  watch(odometry);
  ProgressBar bar("odom_client", source.remaining(), options_.progress);
  const Clock::time_point run_start = Clock::now();
  ScanPreparer input(source, config_, options_.skip_until_seq);
  while (!(options_.stop && options_.stop->load())) {
    const Clock::time_point frame_start = Clock::now();
    const std::optional<PreparedInput> next = input.next();
    if (!next) break;
    if (next->skipped) continue;  // integrated before a restart
    if (!next->scan) {
      std::cerr << "odom_client: skipping " << next->name << ": " << next->problem << "\n";
      continue;
    }
    const PreparedScan& scan = *next->scan;
    if (options_.own_frame && own_since_utime_ < 0) startOwnFrame(odometry, scan);
    if (own_) {
      ownFrameScan(odometry, scan, frame_start);
      bar.tick("own frame");
      continue;
    }
    if (!localized_ && !relocalize(odometry, scan)) {
      if (gave_up_) break;
      bar.tick("relocalizing");
      continue;
    }
    try {
      const FrameStats stats = processScan(odometry, scan, frame_start);
      bar.tick(progressText(stats, tracking_.state()));
    } catch (const IntegrateRefused& e) {
      refused(scan, e.what());
    }
  }
  if (own_search_) finishOwnSearch(odometry);
  pipeline_->close();
  if (recovering_ && !localized_ && !gave_up_)  // the input ended during the search
    sendStatus(robot_status_request_t::LOST, "the input ended before relocalization succeeded",
               trajectory_.seqs.empty() ? 0 : trajectory_.seqs.back(),
               trajectory_.stamps.empty() ? 0 : std::llround(trajectory_.stamps.back() * 1e6));
  if (own_)
    std::cerr << "odom_client: the input ended in the robot's own frame (the shared map was "
                 "not found): nothing of it was integrated; "
              << own_->keyframes().size() << " keyframes kept ("
              << own_->keyframeBytes() / (1024.0 * 1024.0) << " MiB)\n";
  bar.finish();
  wall_seconds_ = std::chrono::duration<double>(Clock::now() - run_start).count();
  if (const RangeCalibration* calibration = odometry.rangeCalibration())
    range_lasers_ = calibration->lasers();
}

FrameStats OdomRunner::processScan(Odometry& odometry, const PreparedScan& prepared,
                                   Clock::time_point start) {
  FrameStats stats;
  stats.frame = prepared.seq;
  stats.preprocess_ms = msSince(start);  // waiting for the scan, read and prepared ahead
  const LocalMap map = pipeline_->target(odometry.predictedPose(prepared).translation(), stats);
  // A correction that came with the Integrate in flight: this target is of the corrected grid.
  applyCorrection(odometry);
  const Clock::time_point register_start = Clock::now();
  FrameEstimate estimate = odometry.registerFrame(prepared, map);
  stats.register_ms = msSince(register_start);
  stats.total_ms = msSince(start);
  // The chunk fetched after this frame serves the frame after the next.
  const Eigen::Vector3d ahead = odometry.predictedPosition(2.0 * odometry.framePeriod());
  if (std::optional<FrameEstimate> first = odometry.takeReleasedFrame()) {
    FrameStats first_stats;  // its time was spent when it arrived
    first_stats.frame = first->seq;
    submit(odometry, std::move(*first), first_stats, ahead);
  }
  if (!estimate.held) submit(odometry, std::move(estimate), stats, ahead);
  return stats;
}

bool OdomRunner::relocalize(Odometry& odometry, const PreparedScan& scan) {
  if (search_since_utime_ < 0) startRelocalizing(scan.utime);
  const double searched = (scan.utime - search_since_utime_) * 1e-6;
  // A recovery searches near the last good pose first (the robot cannot be far from it unless
  // it was carried off), then anywhere.
  if (recovering_ && hint_ && searched > 0.5 * config_.relocalize_timeout) {
    std::cerr << "odom_client: not found near the last good pose: searching the whole map\n";
    hint_.reset();
  }
  FrameStats stats;
  stats.frame = scan.seq;
  stats.status = "relocalizing";
  const Clock::time_point start = Clock::now();
  ServiceMapAccess map(client_, config_);
  const Relocalization found = search_->add(scan, map, hint_);
  stats.register_ms = msSince(start);
  if (!found.pose) {
    stats.problem = found.problem;
    log_->add(stats);
    if (recovering_) {  // one row per scan in the trajectory, as for the lost frames before
      trajectory_.seqs.push_back(scan.seq);
      trajectory_.stamps.push_back(scan.utime * 1e-6);
      trajectory_.poses.push_back(odometry.predictedPose(scan));
    }
    if (searched > config_.relocalize_timeout) giveUp(scan, searched, found.problem);
    return false;
  }
  std::cerr << "odom_client: localized in the map at frame " << scan.seq << " (confirmed on "
            << found.confirmed << " scans; explains " << static_cast<int>(found.fitness * 100)
            << " % of the last " << found.stacked << " scans, "
            << static_cast<int>(found.free * 100) << " % in free space; next place "
            << static_cast<int>(found.runner_up * 100) << " % net)\n";
  // Odometry restarts from the verified pose (the newest stacked scan's at its reference time,
  // deskewed by the search's own odometry) and registers the scan again, now against the shared
  // map and deskewed with the next scan's motion, before anything of it is integrated.
  odometry = Odometry(config_, *found.pose, false);
  watch(odometry);
  const bool was_lost = tracking_.state() == TrackingState::kLost;
  tracking_ = TrackingMonitor(config_.max_unhealthy_frames);
  if (was_lost) sendStatus(robot_status_request_t::TRACKING, "relocalized", scan.seq, scan.utime);
  localized_ = true;
  recovering_ = false;
  search_since_utime_ = -1;
  search_.reset();
  hint_.reset();
  ++relocalizations_;
  return true;
}

void OdomRunner::startRelocalizing(std::int64_t utime) {
  search_since_utime_ = utime;
  search_.emplace(config_);
  std::cerr << "odom_client: searching the robot's pose in the map (relocalization)\n";
}

void OdomRunner::watch(Odometry& odometry) {
  odometry.setSurpriseCheck([this](const FrameEstimate& frame) { return contradictsMap(frame); });
}

std::string OdomRunner::contradictsMap(const FrameEstimate& frame) {
  ServiceMapAccess map(client_, config_);
  const std::vector<Eigen::Vector3f> points =
      localizationPoints(frame.cloud, config_.relocalize_voxel_size, kMaxCheckPoints);
  const std::vector<SpaceCheck> check = map.check(points, {frame.pose});
  if (check.empty() || check[0].free <= config_.relocalize_max_free) return {};
  std::ostringstream out;
  out.precision(2);
  out << frame.health.surprise << ", and " << check[0].free * 100.0
      << " % of the scan lies in the map's free space (> relocalize_max_free)";
  return out.str();
}

void OdomRunner::refused(const PreparedScan& scan, const std::string& why) {
  std::cerr << "odom_client: the server refused an INTEGRATE (" << why
            << "): the robot lost track\n";
  // The refused frame's voxels are in the pipeline's overlay: it starts afresh.
  pipeline_.emplace(client_, config_, *log_);
  tracking_.lose();
  FrameEstimate frame;
  frame.seq = scan.seq;
  frame.utime = scan.utime;
  frame.health.problem = "INTEGRATE refused: " + why;
  reportTracking(TrackingState::kLost, frame);
  if (localized_) startRecovery(frame);
}

void OdomRunner::startRecovery(const FrameEstimate& frame) {
  localized_ = false;  // searched from the next scan on
  recovering_ = true;
  if (last_good_) {
    PoseHint near;
    near.position = last_good_->translation();
    near.radius = config_.relocalize_hint_radius;
    hint_ = near;
  }
  // RELOCALIZING keeps the server refusing its INTEGRATEs until it reports TRACKING again.
  sendStatus(robot_status_request_t::RELOCALIZING, "searching the map", frame.seq, frame.utime);
}

void OdomRunner::giveUp(const PreparedScan& scan, double searched, const std::string& problem) {
  const std::string why = "not localized in the map after " + std::to_string(searched) +
                          " s of scans (relocalize_timeout); last attempt: " + problem;
  if (!recovering_) throw RelocalizationFailed(why);
  std::cerr << "odom_client: " << why << ": the run ends LOST\n";
  sendStatus(robot_status_request_t::LOST, why.substr(0, 200), scan.seq, scan.utime);
  gave_up_ = true;
}

std::optional<Eigen::Isometry3d> OdomRunner::applyCorrection(Odometry& odometry) {
  const std::optional<Eigen::Isometry3d> correction = pipeline_->takeCorrection();
  if (!correction) return std::nullopt;
  odometry.correct(*correction);
  if (last_good_) last_good_ = *correction * *last_good_;
  // Every row added from now on is in the corrected frame; every row before it is not.
  applied_.push_back({trajectory_.seqs.empty() ? std::numeric_limits<std::int64_t>::min()
                                               : trajectory_.seqs.back() + 1,
                      *correction});
  std::ostringstream out;
  out.precision(2);
  out << std::fixed << "map correction: pose moved " << correction->translation().norm() << " m, "
      << Eigen::AngleAxisd(correction->linear()).angle() * 180.0 / M_PI << " deg";
  std::cerr << "odom_client: " << out.str() << " (the map was rebuilt at corrected poses; the "
            << "pose output jumps here)\n";
  jump_ = out.str();
  return correction;
}

void OdomRunner::submit(Odometry& odometry, FrameEstimate estimate, FrameStats stats,
                        const Eigen::Vector3d& ahead) {
  // The Integrate in flight may bring a map correction: this frame, registered in the old
  // frame, is output and integrated in the corrected one (integrate() would wait for it anyway).
  pipeline_->finish();
  if (const std::optional<Eigen::Isometry3d> correction = applyCorrection(odometry))
    estimate.pose = *correction * estimate.pose;
  const TrackingState before = tracking_.state();
  const TrackingState state = tracking_.update(estimate.health.healthy());
  addHealth(estimate, stats);
  stats.status = statusOf(estimate, state);
  if (!jump_.empty())  // the frame whose pose output jumped
    stats.problem = stats.problem.empty() ? std::exchange(jump_, {})
                                          : std::exchange(jump_, {}) + "; " + stats.problem;
  if (!estimate.health.healthy())
    std::cerr << "odom_client: frame " << estimate.seq << " unhealthy (" << estimate.health.problem
              << "): not integrated\n";
  else if (!estimate.health.surprise.empty())
    std::cerr << "odom_client: frame " << estimate.seq << ": kinematic surprise ("
              << estimate.health.surprise << ") with good registration evidence: integrated\n";
  if (state != before) {
    pipeline_->finish();  // the server applies requests in order: the report follows the Integrate
    std::cerr << "odom_client: tracking state " << trackingStateName(state) << " at frame "
              << estimate.seq << "\n";
    reportTracking(state, estimate);
  }
  if (state == TrackingState::kLost && localized_) startRecovery(estimate);
  trajectory_.seqs.push_back(estimate.seq);
  trajectory_.stamps.push_back(estimate.utime * 1e-6);
  trajectory_.poses.push_back(estimate.pose);
  if (state == TrackingState::kLost || !estimate.health.healthy()) {
    pipeline_->finish();  // keeps the frames.csv rows in frame order
    log_->add(stats);
    return;
  }
  stats.integrated = true;
  last_good_ = estimate.pose;
  pipeline_->integrate(std::move(estimate), stats, ahead);
}

void OdomRunner::reportTracking(TrackingState state, const FrameEstimate& frame) {
  // Other robots and operators see it in SOCC/STATUS; a LOST robot's INTEGRATEs are refused by
  // the server too, should anything still send one.
  sendStatus(toWire(state), frame.health.problem.substr(0, 200), frame.seq, frame.utime);
}

void OdomRunner::sendStatus(std::int8_t wire, const std::string& reason, std::int64_t seq,
                            std::int64_t utime) {
  const auto reply = client_.reportTracking(wire, reason, seq, utime);
  // NOT_FOUND: nothing of this robot was integrated yet, so there is nothing to protect.
  if (!reply.ok() && reply.error.status != reply_header_t::NOT_FOUND)
    std::cerr << "odom_client: warning: " << callError("ROBOT_STATUS", reply.error, reply.attempts)
              << "\n";
}

}  // namespace socc::odom
