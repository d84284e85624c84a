#pragma once
// The outcome of a socc-loadtest run and its two renderings: a markdown table for people and
// a JSON file for scripts (scripts/load_test.sh).
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "socc/tools/latency_stats.hpp"

namespace socc::tools {

struct RequestTypeReport {
  std::string name;
  CallStats stats;         // merged over all robots
  bool load_phase = true;  // sent at the target rate (false: one call after the run, no req/s)
};

struct RobotReport {
  std::string client_id;
  std::int64_t sent = 0;            // integrations sent (seq 1..sent)
  std::int64_t unacknowledged = 0;  // no OK reply after all attempts
  std::int64_t not_applied = 0;     // sent - applied according to GET_STATS at the end
  std::int64_t server_last_seq = 0;
  double integrate_hz = 0;  // acknowledged integrations / duration
  double chunk_hz = 0;      // successful chunks / duration
};

struct LoadReport {
  int robots = 0;
  double target_hz = 0;
  double duration_s = 0;
  std::size_t points_per_scan = 0;
  std::string scan_source;
  bool server_stats_ok = false;  // GET_STATS at the end answered
  std::vector<RequestTypeReport> requests;
  std::vector<RobotReport> robot_reports;

  std::int64_t lostIntegrations() const;  // unacknowledged + not applied (max per robot)
  double minAchievedRatio() const;        // min over robots and streams of achieved / target
};

void printMarkdown(const LoadReport& report, std::ostream& out);
void writeJson(const LoadReport& report, std::ostream& out);

}  // namespace socc::tools
