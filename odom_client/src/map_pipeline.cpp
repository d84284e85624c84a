#include "socc/odom/map_pipeline.hpp"

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>

#include "socc/odom/frame_overlay.hpp"
#include "socc/odom/service_map_access.hpp"
#include "socc/pose_conversion.hpp"

namespace socc::odom {
namespace {

using Clock = std::chrono::steady_clock;

// A pipelined chunk centred this far (share of its radius) from the frame is fetched again: the
// frame jumped (relocalization, a lost stretch) or moved much faster than predicted.
constexpr double kMaxCentreShift = 0.2;

}  // namespace

MapPipeline::MapPipeline(rpc::MapClient& client, const OdomConfig& config, FrameLog& log)
    : client_(client), config_(config), log_(log), cache_(config.occupancy_threshold) {}

MapPipeline::~MapPipeline() {
  target_.reset();  // waits for the overlay task
  if (in_flight_ && in_flight_->reply.valid()) in_flight_->reply.wait();
}

LocalMap MapPipeline::target(const Eigen::Vector3d& center, FrameStats& stats) {
  const Clock::time_point start = Clock::now();
  if (!target_ || !covers(*target_, center)) {
    // Fetched now, after the Integrate in flight; it is the target of the next frames too, with
    // their predecessors' voxels, until the worker brings a newer one.
    target_.reset();
    return fetchNow(center, stats);
  }
  Target& t = *target_;
  const Clock::time_point build = Clock::now();
  if (t.pending.valid()) {
    Overlaid next = t.pending.get();
    t.overlay = std::move(next.overlay);
    t.updated = std::move(next.updated);
    t.map = std::move(next.map);
  }
  LocalMap map = t.map;
  pose_epoch_ = map.epoch();
  stats.map_build_ms = msSince(build);
  stats.bytes_received = std::exchange(t.bytes, 0);  // counted once, by its first frame
  stats.chunk_ms = std::exchange(t.chunk_ms, 0.0);
  stats.fetch_ms = msSince(start);
  stats.chunk_voxels = static_cast<std::int64_t>(map.size());
  return map;
}

bool MapPipeline::covers(const Target& target, const Eigen::Vector3d& center) const {
  return (target.center - center).norm() <= kMaxCentreShift * config_.chunk_radius;
}

LocalMap MapPipeline::fetchNow(const Eigen::Vector3d& center, FrameStats& stats) {
  // GET_CHUNK goes out while the previous Integrate may still be unanswered: the server is
  // single-threaded and handles requests in arrival order, so the chunk already holds the
  // previous scan. If the Integrate reached the server after the GET_CHUNK (a retry after a
  // lost datagram, or a worker thread slower to publish than preprocessing), the chunk's map
  // version is older than the Integrate's and it is fetched again.
  const Clock::time_point start = Clock::now();
  rpc::Result<chunk_reply_t> chunk = fetchChunk(center);
  if (chunk.reply->map_version < finish()) {
    chunk = fetchChunk(center);
    ++refetched_chunks_;
  }
  const Clock::time_point build = Clock::now();
  LocalMap map = LocalMap::fromChunk(*chunk.reply, config_.occupancy_threshold);
  stats.map_build_ms = msSince(build);
  stats.fetch_ms = msSince(start);
  stats.chunk_ms = stats.fetch_ms;
  stats.chunk_voxels = static_cast<std::int64_t>(map.size());
  stats.bytes_received = chunk.bytes_received;
  // Taken as it is: nothing else to register against. After a swap the robot was not told of
  // yet, the frame registers into the corrected grid and its Integrate says so (pose_epoch_):
  // the server does not move it a second time.
  frame_gate_.adopt(map.epoch());
  pose_epoch_ = map.epoch();
  held_.reset();
  if (config_.pipelined_map) target_.emplace(Target{map, map, center, 0, 0.0, {}, {}, {}});
  return map;
}

rpc::Result<chunk_reply_t> MapPipeline::fetchChunk(const Eigen::Vector3d& center) {
  rpc::Result<chunk_reply_t> chunk = client_.getChunk(featureChunkRequest(
      center, config_.chunk_radius, config_.occupancy_threshold, config_.pipelined_map));
  if (!chunk.ok()) throw std::runtime_error(callError("GET_CHUNK", chunk.error, chunk.attempts));
  return chunk;
}

void MapPipeline::integrate(FrameEstimate estimate, const FrameStats& stats,
                            const Eigen::Vector3d& ahead) {
  const Clock::time_point wait = Clock::now();
  finish();  // target_ is now the chunk after the previous frame, if one came with it
  if (correction_) estimate.pose = *correction_ * estimate.pose;  // registered in the old frame
  FrameStats row = stats;
  row.wait_ms = msSince(wait);
  row.total_ms += row.wait_ms;
  // Shared by the overlay's and the Integrate's threads: nothing of the scan is copied here.
  const auto frame = std::make_shared<const FrameEstimate>(std::move(estimate));
  if (target_ && !target_->pending.valid())
    startOverlay(frame);
  else
    target_.reset();  // it lacks this frame, and no overlay stands in for it
  // Every chunk_interval-th Integrate brings a chunk back; the frames in between register
  // against the last one plus their predecessors' voxels.
  const bool fetch = config_.pipelined_map && ++integrates_ % config_.chunk_interval == 0;
  in_flight_.emplace();
  in_flight_->stats = row;
  in_flight_->reply =
      std::async(std::launch::async, [this, ahead, fetch, frame, epoch = pose_epoch_]() {
        return exchange(*frame, epoch, fetch ? std::optional(ahead) : std::nullopt);
      });
}

void MapPipeline::startOverlay(std::shared_ptr<const FrameEstimate> frame) {
  // What the frame adds to the target, and the next target with it, worked out while its
  // Integrate travels: voxels the target lacks, and the points it merges into voxels of few
  // points (the chunk's, with their moments, and the overlay's own).
  Target& t = *target_;
  t.pending = std::async(
      std::launch::async, [base = t.map, chunk = t.chunk, overlay = std::move(t.overlay),
                           updated = std::move(t.updated), frame = std::move(frame)]() mutable {
        addFrame(base, chunk.size(), frame->cloud, frame->pose, overlay, updated);
        LocalMap map = chunk.withOverlay(overlay, updated);
        return Overlaid{std::move(overlay), std::move(updated), std::move(map)};
      });
}

MapPipeline::Exchange MapPipeline::exchange(const FrameEstimate& frame, std::int64_t epoch,
                                            const std::optional<Eigen::Vector3d>& fetch_at) {
  Exchange x;
  integrate_request_t request =
      rpc::makeIntegrateRequest(frame.seq, frame.utime, frame.pose, frame.cloud, frame.gravity);
  request.map_epoch = epoch;
  x.bytes_sent = static_cast<std::int64_t>(request.getEncodedSize());
  const Clock::time_point start = Clock::now();
  x.integrate = client_.integrate(std::move(request));
  x.integrate_ms = msSince(start);
  if (!fetch_at || !x.integrate.ok() || closing_) return x;
  const Eigen::Vector3d& ahead = *fetch_at;
  const Clock::time_point fetch = Clock::now();
  if (!config_.delta_chunks) cache_.reset();
  const rpc::Result<chunk_reply_t> chunk =
      client_.getChunk(cache_.request(ahead, config_.chunk_radius));
  if (!chunk.ok()) {  // the next frames fetch theirs (and report the failure)
    cache_.reset();
    return x;
  }
  x.chunk = cache_.apply(*chunk.reply, ahead, config_.chunk_radius);
  x.chunk_version = chunk.reply->map_version;
  x.center = ahead;
  x.chunk_bytes = chunk.bytes_received;
  x.chunk_ms = msSince(fetch);
  return x;
}

std::optional<Eigen::Isometry3d> MapPipeline::takeCorrection() {
  return std::exchange(correction_, std::nullopt);
}

void MapPipeline::close() {
  closing_ = true;
  finish();
}

std::int64_t MapPipeline::finish() {
  if (!in_flight_) return -1;
  Exchange x = in_flight_->reply.get();
  FrameStats stats = in_flight_->stats;
  in_flight_.reset();
  if (!x.integrate.ok() && x.integrate.error.status == reply_header_t::FAILED_PRECONDITION) {
    stats.status = "refused";
    stats.integrated = false;
    stats.problem = x.integrate.error.message;
    log_.add(stats);
    throw IntegrateRefused(x.integrate.error.message);
  }
  if (!x.integrate.ok())
    throw std::runtime_error(callError("INTEGRATE", x.integrate.error, x.integrate.attempts));
  stats.integrate_ms = x.integrate_ms;
  stats.bytes_sent = x.bytes_sent;
  log_.add(stats);
  if (x.integrate.reply->corrected) {
    // The grid was rebuilt at corrected poses: what is cached of the old one is in the old frame
    // (a chunk fetched after this reply is of the new grid).
    const Eigen::Isometry3d correction = fromLcm(x.integrate.reply->correction);
    correction_ = correction_ ? correction * *correction_ : correction;
    pose_epoch_ = x.integrate.reply->map_epoch;  // the frame the correction moves poses into
    target_.reset();
    if (!x.chunk) cache_.reset();
  }
  if (std::optional<Target> next = nextTarget(x)) {
    target_.reset();  // an older chunk (and its overlay) is superseded
    target_.emplace(std::move(*next));
  }
  return x.integrate.reply->map_version;
}

std::optional<MapPipeline::Target> MapPipeline::nextTarget(Exchange& x) {
  // A held chunk waited for this reply: its correction, if any, is told by now.
  std::optional<Target> next = std::exchange(held_, std::nullopt);
  if (next) frame_gate_.adopt(next->chunk.epoch());
  if (!x.chunk) return next;
  Target t{*x.chunk, *x.chunk, x.center, x.chunk_bytes, x.chunk_ms, {}, {}, {}};
  if (frame_gate_.admit(t.chunk.epoch(), x.chunk_version, x.integrate.reply->map_version)) return t;
  held_.emplace(std::move(t));
  ++held_chunks_;
  return next;
}

}  // namespace socc::odom
