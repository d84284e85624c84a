#include "socc/tools/load_robot.hpp"

#include <utility>

#include "socc/wall_clock.hpp"

namespace socc::tools {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Calls tick(k) at start + k * period until stop. A late loop starts the next call at once
// but never makes up more than one missed period, so an overloaded server shows up as a lower
// achieved rate instead of bursts of catch-up requests.
template <typename Tick>
void runAtRate(const RobotSettings& s, Tick&& tick) {
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / s.rate_hz));
  auto next = s.start;
  for (std::int64_t k = 0;; ++k) {
    std::this_thread::sleep_until(next);
    if (Clock::now() >= s.stop) return;
    tick(k);
    next += period;
    if (Clock::now() - next > period) next = Clock::now();
  }
}

// Robots drive at 10 m/s whatever the rate (1 m per frame at 10 Hz), a speed the server's
// plausibility check accepts.
Eigen::Isometry3d poseAt(const RobotSettings& s, std::int64_t frame) {
  return robotPose(s.index, frame, 10.0 / s.rate_hz);
}

}  // namespace

LoadRobot::LoadRobot(RobotSettings settings, const ScanSet& scans)
    : settings_(std::move(settings)), scans_(scans), client_(settings_.client) {
  result_.client_id = settings_.client.client_id;
  integrate_thread_ = std::thread([this] { integrateLoop(); });
  chunk_thread_ = std::thread([this] { chunkLoop(); });
}

LoadRobot::~LoadRobot() {
  join();
}

const RobotResult& LoadRobot::join() {
  if (integrate_thread_.joinable()) integrate_thread_.join();
  if (chunk_thread_.joinable()) chunk_thread_.join();
  return result_;
}

void LoadRobot::integrateLoop() {
  // Scans are stamped at the sensor rate, as a LiDAR does, not when a late loop sends them: the
  // server checks each pose step against the scan-time step.
  const std::int64_t epoch = nowMicros();
  runAtRate(settings_, [this, epoch](std::int64_t frame) {
    const std::int64_t seq = frame + 1;
    const auto pose = poseAt(settings_, frame);
    const auto t0 = Clock::now();
    const std::int64_t utime =
        epoch + static_cast<std::int64_t>(static_cast<double>(frame) * 1e6 / settings_.rate_hz);
    auto request =
        rpc::makeIntegrateRequest(seq, utime, pose, scans_.scan(static_cast<std::size_t>(frame)));
    result_.last_sent_seq = seq;
    const auto r = client_.integrate(std::move(request));
    if (r.ok()) {
      result_.integrate.recordOk(millisecondsSince(t0), r.attempts);
      frame_.store(frame);
      integrations_done_.fetch_add(1);
    } else {
      result_.integrate.recordFailure(r.error.timed_out, r.attempts);
      ++result_.unacknowledged;
    }
  });
}

void LoadRobot::chunkLoop() {
  runAtRate(settings_, [this](std::int64_t) {
    const Eigen::Vector3d centre = poseAt(settings_, frame_.load()).translation();
    const auto t0 = Clock::now();
    const auto r = client_.getChunk(rpc::sphereChunkRequest(centre, settings_.chunk_radius));
    if (r.ok())
      result_.chunk.recordOk(millisecondsSince(t0), r.attempts);
    else
      result_.chunk.recordFailure(r.error.timed_out, r.attempts);
  });
}

}  // namespace socc::tools
