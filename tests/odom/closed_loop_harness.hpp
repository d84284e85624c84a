#pragma once
// The closed loop of odom_client and map_server without the LCM transport: socc-sim scans go
// through the client pipeline (prepare, chunk query of the server's own grid, registration,
// health) and back into that grid. Shared by the closed-loop tests (named namespace, inline:
// test_odom is a unity build).
#include <cstdio>
#include <optional>
#include <vector>

#include "service/chunk_reply.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/labels.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/tracking_state.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/realism.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/scene.hpp"

namespace socc::odom::harness {

// realism: the sensor's error models (sim/README.md "Realism"); none: the exact scan.
inline socc::LabeledCloud simulated(const socc::sim::Scene& scene,
                                    const socc::sim::LidarModel& lidar, int frame, bool distortion,
                                    const socc::sim::Realism* realism = nullptr) {
  const socc::sim::SimulatedScan s =
      socc::sim::simulateScan(scene, lidar, 0.1 * frame, frame, {distortion, 7, realism});
  socc::LabeledCloud c;
  c.points = s.points;
  if (distortion) c.times = s.times;  // taken at one instant otherwise: nothing to deskew
  for (const std::uint32_t raw : s.labels) c.labels.push_back(socc::mapSemanticKittiLabel(raw));
  return c;
}

/// What odom_client fetches: GET_CHUNK (sphere, FIELD_FEATURES) decoded into a LocalMap.
inline LocalMap chunkAround(const socc::map::SemanticOccupancyMap& map,
                            const Eigen::Vector3d& center, const OdomConfig& cfg) {
  socc::map::ChunkQuery query;
  query.center = center;
  query.radius = cfg.chunk_radius;
  query.occupancy_threshold = cfg.occupancy_threshold;
  query.fields = socc::chunk_request_t::FIELD_FEATURES;
  return LocalMap::fromChunk(socc::service::queryChunkReply(map, query), cfg.occupancy_threshold);
}

// What odom_client does per scan, against an in-process grid. Collects the estimated poses.
struct ClosedLoop {
  OdomConfig cfg;
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  Odometry odom;
  TrackingMonitor tracking{cfg.max_unhealthy_frames};
  std::vector<Eigen::Isometry3d> poses;
  int integrated = 0;
  int degenerate = 0;  // frames flagged degenerate

  explicit ClosedLoop(const Eigen::Isometry3d& start, const OdomConfig& config = {})
      : cfg(config), odom(cfg, start, true) {}

  void step(const socc::LabeledCloud& cloud, int frame,
            const std::optional<socc::GravityReference>& gravity = std::nullopt) {
    PreparedScan p = odom.prepare(cloud, frame, frame * 100000);
    p.gravity = gravity;
    const FrameEstimate e =
        odom.registerFrame(p, chunkAround(map, odom.predictedPose(p).translation(), cfg));
    if (auto first = odom.takeReleasedFrame()) submit(*first);
    if (!e.held) submit(e);
  }
  void submit(const FrameEstimate& e) {
    poses.push_back(e.pose);
    if (e.health.degenerate) ++degenerate;
    if (!e.health.healthy())
      std::printf("frame %lld unhealthy: %s\n", static_cast<long long>(e.seq),
                  e.health.problem.c_str());
    if (tracking.update(e.health.healthy()) == TrackingState::kLost || !e.health.healthy()) return;
    map.integrate(e.pose, e.cloud);
    ++integrated;
  }
};

}  // namespace socc::odom::harness
