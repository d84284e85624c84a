#pragma once
// One simulated robot of socc-loadtest: its own MapClient (own client id) and two fixed-rate
// loops, as on a real robot: one integrates scans, the other fetches the local map chunk
// around the robot (MapClient supports concurrent calls). Both loops stop at the deadline and
// finish the call in flight, which is bounded by the client's timeout x attempts.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include "socc/rpc/map_client.hpp"
#include "socc/tools/latency_stats.hpp"
#include "socc/tools/load_scans.hpp"

namespace socc::tools {

struct RobotSettings {
  int index = 0;
  rpc::ClientOptions client;
  double rate_hz = 10.0;
  double chunk_radius = 20.0;
  std::chrono::steady_clock::time_point start;
  std::chrono::steady_clock::time_point stop;  // no call is started at or after this
};

/// What one robot observed; read after join().
struct RobotResult {
  std::string client_id;
  CallStats integrate;
  CallStats chunk;
  std::int64_t last_sent_seq = 0;   // seqs 1..last_sent_seq were sent
  std::int64_t unacknowledged = 0;  // sent seqs without an OK reply (duplicate counts as OK)
};

class LoadRobot {
 public:
  LoadRobot(RobotSettings settings, const ScanSet& scans);
  ~LoadRobot();  // joins
  LoadRobot(const LoadRobot&) = delete;
  LoadRobot& operator=(const LoadRobot&) = delete;

  /// Integrations completed so far (for the progress line).
  std::int64_t integrationsDone() const { return integrations_done_.load(); }
  /// Waits for both loops; the result is complete afterwards.
  const RobotResult& join();

 private:
  void integrateLoop();
  void chunkLoop();

  RobotSettings settings_;
  const ScanSet& scans_;
  rpc::MapClient client_;
  RobotResult result_;
  std::atomic<std::int64_t> integrations_done_{0};
  std::atomic<std::int64_t> frame_{0};  // latest integrated frame: where the chunk is fetched
  std::thread integrate_thread_;
  std::thread chunk_thread_;
};

}  // namespace socc::tools
