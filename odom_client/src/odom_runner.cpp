#include "socc/odom/odom_runner.hpp"

#include <chrono>
#include <future>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "socc/odom/local_map.hpp"
#include "socc/odom/odometry.hpp"
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
  Odometry odometry(config_, options_.initial_pose);
  ProgressBar bar("odom_client", source.remaining(), options_.progress);
  const Clock::time_point run_start = Clock::now();
  std::optional<PendingIntegrate> pending;
  std::optional<std::int64_t> last_utime;

  // Waits for the Integrate in flight, then logs its frame.
  const auto finishPending = [&]() {
    if (!pending) return;
    auto [result, latency_ms] = pending->reply.get();
    if (!result.ok())
      throw std::runtime_error(callError("INTEGRATE", result.error, result.attempts));
    pending->stats.integrate_ms = latency_ms;
    log.add(pending->stats);
    pending.reset();
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

    finishPending();  // the server has applied the previous scan before we ask for the chunk

    const Clock::time_point fetch_start = Clock::now();
    const Eigen::Isometry3d prediction = odometry.predictedPose();
    chunk_request_t request =
        rpc::sphereChunkRequest(prediction.translation(), config_.chunk_radius);
    request.occupancy_threshold = static_cast<float>(config_.occupancy_threshold);
    const rpc::Result<chunk_reply_t> chunk = client_.getChunk(request);
    if (!chunk.ok()) throw std::runtime_error(callError("GET_CHUNK", chunk.error, chunk.attempts));
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

    // The full range-filtered (deskewed) cloud goes to the map, not the downsampled one.
    integrate_request_t integrate =
        rpc::makeIntegrateRequest(scan->seq, scan->utime, estimate.pose, prepared.full);
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
