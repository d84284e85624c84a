#pragma once
// A socc-sim street for the service tests that search (LOCALIZE): its scans, a map of them and
// a server config whose search fits a small map.
#include <string>
#include <vector>

#include "service/service_config.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/scene.hpp"

namespace socc::service::test {

inline sim::Scene street() {
  sim::SceneOptions options;
  options.frames = 20;
  options.seed = 7;
  return sim::buildScene(options);
}

/// Every 4th point of frame k (VLP-32, no distortion), sensor frame.
inline std::vector<Eigen::Vector3f> simulatedPoints(const sim::Scene& scene, int k) {
  const sim::SimulatedScan s =
      sim::simulateScan(scene, sim::lidarPreset("vlp32"), 0.1 * k, static_cast<std::uint64_t>(k),
                        {false, 11, nullptr});
  std::vector<Eigen::Vector3f> out;
  for (std::size_t i = 0; i < s.points.size(); i += 4) out.push_back(s.points[i]);
  return out;
}

/// Frame k at its true pose, from robot "mapper".
inline integrate_request_t streetIntegrate(const sim::Scene& scene, int k) {
  LabeledCloud cloud;
  cloud.points = simulatedPoints(scene, k);
  cloud.labels.assign(cloud.points.size(), 0);
  integrate_request_t request =
      rpc::makeIntegrateRequest(k, k * 100000, scene.trajectory.poseAt(0.1 * k), cloud);
  request.header.client_id = "mapper";
  return request;
}

/// The budget of the in-process relocalization tests' small maps (test_relocalization.cpp),
/// smaller still: these tests check the threading, not the search's recall.
inline ServerConfig searchConfig(int max_waiting) {
  ServerConfig config;
  config.localization.search.max_iterations = 3'000;
  config.limits.max_waiting_searches = max_waiting;
  return config;
}

}  // namespace socc::service::test
