#include "socc/tools/load_report.hpp"

#include <algorithm>
#include <iomanip>

namespace socc::tools {

namespace {

// A robot's seq can be both unacknowledged and not applied; count each lost seq once.
std::int64_t lostOf(const RobotReport& r) {
  return std::max(r.unacknowledged, r.not_applied);
}

}  // namespace

std::int64_t LoadReport::lostIntegrations() const {
  std::int64_t lost = 0;
  for (const auto& r : robot_reports) lost += lostOf(r);
  return lost;
}

double LoadReport::minAchievedRatio() const {
  double ratio = robot_reports.empty() ? 0.0 : 1e9;
  for (const auto& r : robot_reports)
    ratio = std::min({ratio, r.integrate_hz / target_hz, r.chunk_hz / target_hz});
  return ratio;
}

void printMarkdown(const LoadReport& report, std::ostream& out) {
  out << std::fixed << std::setprecision(1);
  out << "\n### socc-loadtest: " << report.robots << " robot(s), " << report.target_hz
      << " Hz target, " << report.duration_s << " s, " << report.points_per_scan << " points/scan ("
      << report.scan_source << ")\n\n";
  out << "| request | calls | ok | req/s | p50 ms | p90 ms | p99 ms | max ms | timeouts | "
         "retries | errors |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : report.requests) {
    const LatencySummary l = r.stats.summary();
    out << "| " << r.name << " | " << r.stats.calls() << " | " << r.stats.succeeded() << " | ";
    if (r.load_phase)
      out << static_cast<double>(r.stats.succeeded()) / report.duration_s;
    else
      out << '-';
    out << " | " << l.p50_ms << " | " << l.p90_ms << " | " << l.p99_ms << " | " << l.max_ms << " | "
        << r.stats.timeouts() << " | " << r.stats.retries() << " | " << r.stats.errors() << " |\n";
  }
  out << "\n| robot | sent | unacked | not applied | server last seq | integrate Hz | chunk Hz | "
         "target Hz | achieved % |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : report.robot_reports) {
    const double pct = 100.0 * std::min(r.integrate_hz, r.chunk_hz) / report.target_hz;
    out << "| " << r.client_id << " | " << r.sent << " | " << r.unacknowledged << " | "
        << r.not_applied << " | " << r.server_last_seq << " | " << r.integrate_hz << " | "
        << r.chunk_hz << " | " << report.target_hz << " | " << pct << " |\n";
  }
  if (!report.server_stats_ok)
    out << "\nGET_STATS at the end failed: every integration counts as not applied.\n";
  out << "\nsummary: robots=" << report.robots << " target_hz=" << report.target_hz
      << " min_achieved_pct=" << 100.0 * report.minAchievedRatio()
      << " lost=" << report.lostIntegrations() << '\n';
}

void writeJson(const LoadReport& report, std::ostream& out) {
  out << std::setprecision(6) << "{\n  \"robots\": " << report.robots
      << ",\n  \"target_hz\": " << report.target_hz << ",\n  \"duration_s\": " << report.duration_s
      << ",\n  \"points_per_scan\": " << report.points_per_scan
      << ",\n  \"server_stats_ok\": " << (report.server_stats_ok ? "true" : "false")
      << ",\n  \"lost_integrations\": " << report.lostIntegrations()
      << ",\n  \"min_achieved_ratio\": " << report.minAchievedRatio() << ",\n  \"requests\": [";
  for (std::size_t i = 0; i < report.requests.size(); ++i) {
    const auto& r = report.requests[i];
    const LatencySummary l = r.stats.summary();
    out << (i ? "," : "") << "\n    {\"name\": \"" << r.name << "\", \"calls\": " << r.stats.calls()
        << ", \"ok\": " << r.stats.succeeded() << ", \"req_per_s\": "
        << (r.load_phase ? static_cast<double>(r.stats.succeeded()) / report.duration_s : 0.0)
        << ", \"p50_ms\": " << l.p50_ms << ", \"p90_ms\": " << l.p90_ms
        << ", \"p99_ms\": " << l.p99_ms << ", \"max_ms\": " << l.max_ms
        << ", \"timeouts\": " << r.stats.timeouts() << ", \"retries\": " << r.stats.retries()
        << ", \"errors\": " << r.stats.errors() << "}";
  }
  out << "\n  ],\n  \"robot_results\": [";
  for (std::size_t i = 0; i < report.robot_reports.size(); ++i) {
    const auto& r = report.robot_reports[i];
    // client ids are [A-Za-z0-9_.-] (checked by MapClient), so they need no JSON escaping.
    out << (i ? "," : "") << "\n    {\"client_id\": \"" << r.client_id << "\", \"sent\": " << r.sent
        << ", \"unacknowledged\": " << r.unacknowledged << ", \"not_applied\": " << r.not_applied
        << ", \"server_last_seq\": " << r.server_last_seq
        << ", \"integrate_hz\": " << r.integrate_hz << ", \"chunk_hz\": " << r.chunk_hz << "}";
  }
  out << "\n  ]\n}\n";
}

}  // namespace socc::tools
