#include "socc/odom/odom_runner.hpp"

#include <chrono>
#include <future>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "socc/odom/local_map.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/progress_bar.hpp"

namespace socc::odom {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::string callError(const char* what, const rpc::CallError& e, int attempts) {
  std::ostringstream out;
  out << what << " failed after " << attempts << " attempt(s): "
      << (e.timed_out ? "no reply from the map server (is map_server running on this LCM URL?)"
                      : e.message + " (status " + std::to_string(e.status) + ")");
  return out.str();
}

// One Integrate in flight, answered in a worker thread; its row of stats waits with it.
struct PendingIntegrate {
  std::future<std::pair<rpc::Result<integrate_reply_t>, double>> reply;  // result, latency ms
  FrameStats stats;
};

}  // namespace

OdomRunner::OdomRunner(const OdomConfig& config, rpc::MapClient& client, RunOptions options)
    : config_(config), client_(client), options_(options) {}

void OdomRunner::run(ScanSource& source, FrameLog& log) {
  Odometry odometry(config_, options_.initial_pose, options_.initial_pose_known);
  ProgressBar bar("odom_client", source.remaining(), options_.progress);
  const Clock::time_point run_start = Clock::now();
  std::optional<PendingIntegrate> pending;
  std::optional<std::int64_t> last_utime;

  // Waits for the Integrate in flight, logs its frame and returns the map version it produced
  // (-1 when none was in flight).
  const auto finishPending = [&]() -> std::int64_t {
    if (!pending) return -1;
    auto [result, latency_ms] = pending->reply.get();
    if (!result.ok())
      throw std::runtime_error(callError("INTEGRATE", result.error, result.attempts));
    pending->stats.integrate_ms = latency_ms;
    log.add(pending->stats);
    pending.reset();
    return result.reply->map_version;
  };
  const auto fetchChunk = [&](const Eigen::Vector3d& center) {
    chunk_request_t request = rpc::sphereChunkRequest(center, config_.chunk_radius);
    request.occupancy_threshold = static_cast<float>(config_.occupancy_threshold);
    rpc::Result<chunk_reply_t> chunk = client_.getChunk(request);
    if (!chunk.ok()) throw std::runtime_error(callError("GET_CHUNK", chunk.error, chunk.attempts));
    return chunk;
  };

  while (!(options_.stop && options_.stop->load())) {
    const Clock::time_point frame_start = Clock::now();
    std::optional<Scan> scan = source.next();
    if (!scan) break;
    if (scan->seq <= options_.skip_until_seq) continue;  // integrated before a restart

    FrameStats stats;
    stats.frame = scan->seq;
    const double period = last_utime && scan->utime > *last_utime
                              ? (scan->utime - *last_utime) * 1e-6
                              : config_.frame_period;
    last_utime = scan->utime;
    PreparedScan prepared;
    try {
      prepared = odometry.prepare(scan->cloud, period);
    } catch (const std::invalid_argument& e) {
      std::cerr << "odom_client: skipping " << scan->name << ": " << e.what() << "\n";
      continue;
    }
    stats.preprocess_ms = msSince(frame_start);
    stats.points = static_cast<std::int64_t>(prepared.full.size());
    stats.downsampled_points = static_cast<std::int64_t>(prepared.downsampled.size());

    // The full range-filtered (deskewed) cloud goes to the map, not the downsampled one. It is
    // in the sensor frame, so the request is built here, off the critical path (the server is
    // still integrating the previous scan); only the estimated pose is filled in later.
    integrate_request_t integrate = rpc::makeIntegrateRequest(
        scan->seq, scan->utime, Eigen::Isometry3d::Identity(), prepared.full);

    // GET_CHUNK goes out while the previous Integrate may still be unanswered: the server is
    // single-threaded and handles requests in arrival order, so the chunk already holds the
    // previous scan. If the Integrate reached the server after the GET_CHUNK (a retry after a
    // lost datagram, or a worker thread slower to publish than preprocessing), the chunk's map
    // version is older than the Integrate's and it is fetched again.
    const Clock::time_point fetch_start = Clock::now();
    const Eigen::Vector3d center = odometry.predictedPose().translation();
    rpc::Result<chunk_reply_t> chunk = fetchChunk(center);
    if (chunk.reply->map_version < finishPending()) {
      chunk = fetchChunk(center);
      ++refetched_chunks_;
    }
    const LocalMap map = LocalMap::fromChunk(*chunk.reply, config_.occupancy_threshold);
    stats.fetch_ms = msSince(fetch_start);
    stats.chunk_voxels = static_cast<std::int64_t>(map.size());
    stats.bytes_received = chunk.bytes_received;

    const Clock::time_point register_start = Clock::now();
    const FrameEstimate estimate = odometry.registerFrame(prepared, map);
    stats.register_ms = msSince(register_start);
    stats.planar = estimate.registration.planar;
    stats.non_planar = estimate.registration.non_planar;
    stats.alpha = estimate.registration.alpha;
    stats.iterations = estimate.registration.iterations;
    stats.sigma = estimate.sigma;

    integrate.sensor_pose = toLcm(estimate.pose);
    pending.emplace();
    pending->reply =
        std::async(std::launch::async, [this, request = std::move(integrate)]() mutable {
          const Clock::time_point start = Clock::now();
          auto result = client_.integrate(std::move(request));
          return std::make_pair(std::move(result), msSince(start));
        });
    stats.total_ms = msSince(frame_start);
    pending->stats = stats;

    trajectory_.seqs.push_back(scan->seq);
    trajectory_.stamps.push_back(scan->utime * 1e-6);
    trajectory_.poses.push_back(estimate.pose);
    std::ostringstream extra;
    extra.precision(1);
    extra << std::fixed << "register " << stats.register_ms << " ms, " << map.size() << " voxels";
    bar.tick(extra.str());
  }
  finishPending();
  bar.finish();
  wall_seconds_ = std::chrono::duration<double>(Clock::now() - run_start).count();
}

}  // namespace socc::odom
