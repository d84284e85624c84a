#include "map_service.hpp"

#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "plausibility.hpp"
#include "request_checks.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/version.hpp"
#include "socc/wall_clock.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::service {
namespace {

constexpr auto kRateWindow = std::chrono::seconds(5);

LabeledCloud toCloud(const integrate_request_t& request) {
  LabeledCloud cloud;
  cloud.points = wire::pointsFromQuantized(request.xyz, request.xyz_resolution);
  cloud.labels = request.label;
  cloud.times = request.time;
  return cloud;
}

}  // namespace

MapService::MapService(const ServerConfig& config)
    : config_(config), map_(config.map), localizer_(config.localization) {
  if (config.consistency.enabled)
    consistency_ =
        std::make_unique<consistency::ConsistencyService>(config.consistency, config.map);
  corrections_.serving(map_.epoch());
}

integrate_reply_t MapService::integrate(const integrate_request_t& request,
                                        const std::uint8_t* received, std::size_t received_size) {
  integrate_reply_t reply{};
  reply.seq = request.seq;
  setStatus(reply, applyIntegrate(request, reply, true, received, received_size));
  reply.map_version = map_.version();
  reply.map_epoch = map_.epoch();
  return reply;
}

Status MapService::applyIntegrate(const integrate_request_t& request, integrate_reply_t& reply,
                                  bool judge, const std::uint8_t* received,
                                  std::size_t received_size) {
  if (Status s = checkIntegrateRequest(request, map_.config()); !s.ok()) return s;
  const std::string& robot_id = request.header.client_id;
  // A retry (same seq) or an old message (lower seq) was applied before: acknowledge only.
  if (robots_.isDuplicate(robot_id, request.seq)) {
    reply.duplicate = true;
    if (const auto told = corrections_.toldWith(robot_id, request.seq)) {
      reply.corrected = true;
      reply.correction = toLcm(*told);
    }
    return {};
  }
  // A journal replay keeps the grid it rebuilds (the swap's checkpoint holds a corrected one).
  if (judge && consistency_) swapInRebuiltGrid();
  // Two robots founding at once would write two unrelated frames into one grid: requests are
  // applied one at a time, so the first founds and the others are told to search the map.
  if (judge && request.map_epoch == integrate_request_t::FOUND_MAP && !holdsNothing())
    return Status::failedPrecondition(
        "the map is not empty (founded by another robot, or loaded): a robot founds an empty map "
        "only; search it instead");
  if (Status s = admitRobot(request, judge); !s.ok()) return s;
  const LabeledCloud cloud = toCloud(request);
  const Eigen::Isometry3d sent = fromLcm(request.sensor_pose);
  if (const std::string why = map_.validate(sent, cloud); !why.empty()) return Status::invalid(why);
  // The pose as the robot sent it, in its first frame (for the pose graph) and in the grid's.
  const RobotCorrections::Incoming at =
      corrections_.incoming(robot_id, request.seq, sent, request.map_epoch);
  const Eigen::Isometry3d& pose = at.map;
  if (!at.map.isApprox(sent))
    if (const std::string why = map_.validate(pose, cloud); !why.empty())
      return Status::invalid(why);

  // Write-ahead: journal first, so an acknowledged Integrate is never lost by a crash.
  if (journal_) {
    // The received bytes as they are: no re-encode of a 1.6 MB scan, and the journal holds
    // exactly what the client sent (and signed).
    std::vector<std::uint8_t> encoded;
    if (received == nullptr) {
      encoded.resize(static_cast<std::size_t>(request.getEncodedSize()));
      request.encode(encoded.data(), 0, static_cast<int>(encoded.size()));
      received = encoded.data();
      received_size = encoded.size();
    }
    try {
      journal_->append(received, received_size);
    } catch (const std::exception& e) {
      return Status::internal(std::string("not applied: ") + e.what());
    }
  }
  const map::IntegrationResult result = map_.integrate(pose, cloud);
  robots_.recordIntegration(robot_id, request.seq, request.scan_utime, toLcm(pose));
  if (consistency_)
    consistency_->observe(robot_id, request.seq, request.scan_utime, at.raw, cloud,
                          consistency::gravityReference(
                              Eigen::Map<const Eigen::Vector3f>(request.gravity_up).cast<double>(),
                              static_cast<double>(request.gravity_sigma)));
  if (at.told) {
    reply.corrected = true;
    reply.correction = toLcm(*at.told);
  }
  ++integrations_;
  const auto now = std::chrono::steady_clock::now();
  recent_integrations_.push_back(now);
  while (!recent_integrations_.empty() && now - recent_integrations_.front() > kRateWindow)
    recent_integrations_.pop_front();

  reply.voxels_touched = result.voxels_touched;
  reply.voxels_hit = result.voxels_hit;
  reply.voxels_freed = result.voxels_freed;
  return {};
}

void MapService::restartConsistency() {
  if (!consistency_) return;
  consistency::ConsistencyParams params = config_.consistency;
  const bool foreign = map_.stats().num_voxels != 0;
  params.correct_grid = params.correct_grid && !foreign;
  consistency_foreign_ = foreign;
  consistency_.reset();  // its worker stops writing before the store is replaced
  consistency_ = std::make_unique<consistency::ConsistencyService>(
      params, config_.map, odom::OdomConfig{}, newConsistencyStore(foreign));
}

void MapService::swapInRebuiltGrid() {
  std::unique_ptr<consistency::RebuiltGrid> grid = consistency_->takeRebuild();
  if (!grid) return;
  grid->map.continueVersion(map_.version());
  map_ = std::move(grid->map);
  corrections_.corrected(map_.epoch(), grid->corrections);
  ++map_corrections_;
  if (!journal_) return;
  try {
    checkpoint();  // a restart must not replay old-frame scans onto the corrected grid's base
  } catch (const std::exception& e) {
    std::cerr << "map_server: warning: no checkpoint of the corrected grid (" << e.what()
              << "): a restart replays the journal onto the last snapshot, uncorrected\n";
  }
}

bool MapService::holdsNothing() const {
  return robots_.size() == 0 && map_.stats().num_voxels == 0;
}

Status MapService::admitRobot(const integrate_request_t& request, bool judge) {
  const std::string& robot_id = request.header.client_id;
  const robot_state_t* robot = robots_.find(robot_id);
  if (robot == nullptr) {
    if (static_cast<std::int64_t>(robots_.size()) < config_.limits.max_robots) return {};
    return Status::exhausted("the server already tracks " + std::to_string(robots_.size()) +
                             " robots (limits.max_robots)");
  }
  if (!judge) return {};
  Status admitted =
      admitIntegrate(*robot, robots_.anchored(robot_id), request, config_.plausibility);
  if (!admitted.ok()) robots_.recordRefusal(robot_id);
  return admitted;
}

double MapService::integrationsPerSecond() const {
  const auto now = std::chrono::steady_clock::now();
  std::int64_t count = 0;
  for (const auto& t : recent_integrations_) count += (now - t <= kRateWindow) ? 1 : 0;
  return static_cast<double>(count) / std::chrono::duration<double>(kRateWindow).count();
}

map_stats_t MapService::stats(const RequestCounters& counters) const {
  const map::MapStats m = map_.stats();
  map_stats_t out{};
  out.utime = nowMicros();
  out.server_version = kVersion;
  out.voxel_size = map_.config().voxel_size;
  out.num_voxels = m.num_voxels;
  out.num_occupied = m.num_occupied;
  out.num_free = m.num_free;
  out.num_blocks = m.num_blocks;
  out.memory_bytes = m.memory_bytes;
  out.map_version = map_.version();
  out.integrations = integrations_;
  out.integrations_per_s = integrationsPerSecond();
  out.requests = counters.requests;
  out.rejected_requests = counters.rejected;
  out.auth_failures = counters.auth_failures;
  out.robots = robots_.states();
  out.num_robots = static_cast<std::int32_t>(out.robots.size());
  return out;
}

stats_reply_t MapService::getStats(const stats_request_t& /*request*/,
                                   const RequestCounters& counters) const {
  stats_reply_t reply{};
  reply.stats = stats(counters);
  return reply;
}

robot_status_reply_t MapService::robotStatus(const robot_status_request_t& request) {
  robot_status_reply_t reply{};
  reply.state.last_pose.quaternion[0] = 1.0;
  if (Status s = checkRobotStatusRequest(request); !s.ok()) return setStatus(reply, s);
  const std::string& robot_id = request.header.client_id;
  // Only robots with a pose in the map have integrations to refuse (and a registry entry).
  if (!robots_.recordTracking(robot_id, request.seq, request.utime, request.tracking_state,
                              request.reason))
    return setStatus(reply,
                     Status::notFound("robot '" + robot_id + "' has no accepted INTEGRATE yet"));
  reply.state = *robots_.find(robot_id);
  return reply;
}

robot_pose_reply_t MapService::getRobotPose(const robot_pose_request_t& request) const {
  robot_pose_reply_t reply{};
  reply.state.last_pose.quaternion[0] = 1.0;
  const robot_state_t* state = robots_.find(request.robot_id);
  if (state == nullptr) {
    const std::string shown = request.robot_id.substr(0, 64);
    setStatus(reply, Status::notFound("unknown robot '" + shown + "'"));
    return reply;
  }
  reply.state = *state;
  if (request.max_history < 0) {
    setStatus(reply, Status::invalid("max_history must be >= 0"));
    return reply;
  }
  if (request.max_history > 0) {
    // 10000 poses (~0.6 MB) per reply keep a whole day's history from becoming one huge message.
    constexpr std::size_t kMaxHistoryPerReply = 10000;
    const std::size_t max_poses =
        std::min(static_cast<std::size_t>(request.max_history), kMaxHistoryPerReply);
    bool truncated = false;
    reply.history =
        robots_.history(request.robot_id, request.history_from_seq, max_poses, &truncated);
    reply.history_truncated = truncated;
  }
  return reply;
}

}  // namespace socc::service
