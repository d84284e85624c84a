// socc-loadtest: N simulated robots integrate KITTI-size scans and fetch local chunks at a
// fixed rate against a running map_server, then a markdown table (and optionally JSON)
// reports throughput, latency percentiles, timeouts/retries, errors, lost integrations and the
// achieved rate. Exit code 0 when no integration was lost, 1 otherwise, 2 on bad usage.
#include <CLI/CLI.hpp>
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "socc/large_message_heap.hpp"
#include "socc/lcm_url.hpp"
#include "socc/progress_bar.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/tools/load_report.hpp"
#include "socc/tools/load_robot.hpp"
#include "socc/tools/load_scans.hpp"
#include "socc/tools/server_process.hpp"
#include "socc/version.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using socc::tools::LoadReport;

struct Options {
  int robots = 4;
  double rate_hz = 10.0;
  double duration_s = 15.0;
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=67108864";
  double chunk_radius = 20.0;
  std::string kitti_dir;
  std::size_t synthetic_points = 120'000;
  std::string start_server;
  std::string json_file;
  std::string id_prefix;
  int timeout_ms = 1000;
  int attempts = 3;
  bool progress = true;
};

// A fresh prefix per run: the server remembers each client id's last seq, so a second run
// against the same server with the same ids would only get duplicates.
std::string randomIdPrefix() {
  std::random_device rd;
  std::ostringstream s;
  s << "load-" << std::hex << (rd() & 0xffffffu);
  return s.str();
}

socc::rpc::ClientOptions clientOptions(const Options& o, const std::string& id) {
  socc::rpc::ClientOptions c;
  c.lcm_url = o.lcm_url;
  c.client_id = id;
  c.timeout = std::chrono::milliseconds(o.timeout_ms);
  c.max_attempts = o.attempts;
  return c;
}

// Polls GET_STATS until the server answers (it may still be starting), at most ~10 s.
bool waitForServer(const Options& o, socc::tools::ServerProcess* server) {
  auto probe = clientOptions(o, o.id_prefix + "-probe");
  probe.timeout = std::chrono::milliseconds(200);
  probe.max_attempts = 1;
  socc::rpc::MapClient client(probe);
  for (int i = 0; i < 50; ++i) {
    if (client.getStats().ok()) return true;
    if (server && !server->running()) return false;
  }
  return false;
}

// Runs the robots for the duration with a progress bar; returns when every call has finished.
std::vector<socc::tools::RobotResult> runRobots(const Options& o,
                                                const socc::tools::ScanSet& scans) {
  const auto start = Clock::now() + std::chrono::milliseconds(200);  // clients subscribed
  const auto stop = start + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>(o.duration_s));
  std::vector<std::unique_ptr<socc::tools::LoadRobot>> robots;
  for (int r = 0; r < o.robots; ++r) {
    socc::tools::RobotSettings s;
    s.index = r;
    s.client = clientOptions(o, o.id_prefix + "-r" + std::to_string(r));
    s.rate_hz = o.rate_hz;
    s.chunk_radius = o.chunk_radius;
    s.start = start;
    s.stop = stop;
    robots.push_back(std::make_unique<socc::tools::LoadRobot>(s, scans));
  }
  constexpr auto kTick = std::chrono::milliseconds(250);
  socc::ProgressBar bar("load", static_cast<std::size_t>(o.duration_s * 4.0), o.progress);
  for (auto t = start + kTick; t <= stop; t += kTick) {
    std::this_thread::sleep_until(t);
    std::int64_t done = 0;
    for (const auto& robot : robots) done += robot->integrationsDone();
    bar.tick(std::to_string(done) + " integrations");
  }
  bar.finish();
  std::vector<socc::tools::RobotResult> results;
  for (auto& robot : robots) results.push_back(robot->join());  // drain: bounded by timeouts
  return results;
}

LoadReport buildReport(const Options& o, const socc::tools::ScanSet& scans,
                       const std::vector<socc::tools::RobotResult>& results) {
  LoadReport report;
  report.robots = o.robots;
  report.target_hz = o.rate_hz;
  report.duration_s = o.duration_s;
  report.points_per_scan = scans.averagePoints();
  report.scan_source = o.kitti_dir.empty() ? "synthetic" : "KITTI " + o.kitti_dir;
  report.requests = {{"INTEGRATE", {}, true}, {"GET_CHUNK", {}, true}, {"GET_STATS", {}, false}};
  for (const auto& r : results) {
    report.requests[0].stats.merge(r.integrate);
    report.requests[1].stats.merge(r.chunk);
  }
  // The server's view: what each robot's seq stream left in the map.
  socc::rpc::MapClient client(clientOptions(o, o.id_prefix + "-stats"));
  const auto t0 = Clock::now();
  const auto stats = client.getStats();
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  if (stats.ok())
    report.requests[2].stats.recordOk(ms, stats.attempts);
  else
    report.requests[2].stats.recordFailure(stats.error.timed_out, stats.attempts);
  report.server_stats_ok = stats.ok();
  for (const auto& r : results) {
    socc::tools::RobotReport rr;
    rr.client_id = r.client_id;
    rr.sent = r.last_sent_seq;
    rr.unacknowledged = r.unacknowledged;
    rr.not_applied = r.last_sent_seq;
    if (stats.ok())
      for (const auto& state : stats.reply->stats.robots)
        if (state.robot_id == r.client_id) {
          rr.server_last_seq = state.last_seq;
          rr.not_applied = r.last_sent_seq - state.integrations;
        }
    rr.integrate_hz = static_cast<double>(r.integrate.succeeded()) / o.duration_s;
    rr.chunk_hz = static_cast<double>(r.chunk.succeeded()) / o.duration_s;
    report.robot_reports.push_back(rr);
  }
  return report;
}

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--robots", o.robots, "simulated robots")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--rate", o.rate_hz, "integrations and chunk queries per robot [Hz]")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--duration", o.duration_s, "load phase [s]; then in-flight calls drain")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 3600.0));
  app.add_option("--lcm-url", o.lcm_url, "udpm://239.x.y.z:port?ttl=0 (add recv_buf_size)")
      ->capture_default_str();
  app.add_option("--chunk-radius", o.chunk_radius, "radius of the chunk sphere [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--kitti", o.kitti_dir,
                 "KITTI sequence dir (velodyne/, labels/); default: "
                 "synthetic scans")
      ->check(CLI::ExistingDirectory);
  app.add_option("--synthetic-points", o.synthetic_points, "points of the synthetic scan")
      ->capture_default_str()
      ->check(CLI::Range(64, 2'000'000));
  app.add_option("--start-server", o.start_server,
                 "map_server binary to start on --lcm-url and stop at the end")
      ->check(CLI::ExistingFile);
  app.add_option("--json", o.json_file, "also write the results as JSON");
  app.add_option("--id-prefix", o.id_prefix, "client id prefix (default: random per run)");
  app.add_option("--timeout-ms", o.timeout_ms, "per attempt")
      ->capture_default_str()
      ->check(CLI::Range(10, 60000));
  app.add_option("--attempts", o.attempts, "attempts per call")
      ->capture_default_str()
      ->check(CLI::Range(1, 10));
  app.add_flag("!--no-progress", o.progress, "no progress bar");
}

// Loads the scans, waits for (or starts) the server, runs the robots and reports; the exit code.
int run(Options o) {
  if (o.id_prefix.empty()) o.id_prefix = randomIdPrefix();
  try {
    const auto scans = o.kitti_dir.empty() ? socc::tools::ScanSet::synthetic(o.synthetic_points)
                                           : socc::tools::ScanSet::fromKitti(o.kitti_dir);
    std::optional<socc::tools::ServerProcess> server;
    if (!o.start_server.empty()) server.emplace(o.start_server, o.lcm_url);
    if (!waitForServer(o, server ? &*server : nullptr)) {
      std::cerr << "socc-loadtest: map_server does not answer on " << o.lcm_url << '\n';
      return 1;
    }
    std::cerr << "socc-loadtest: " << o.robots << " robot(s) at " << o.rate_hz << " Hz for "
              << o.duration_s << " s (drain <= " << o.timeout_ms * o.attempts / 1000.0 << " s), "
              << scans.averagePoints() << " points/scan, ids " << o.id_prefix << "-r*\n";
    const auto results = runRobots(o, scans);
    const LoadReport report = buildReport(o, scans, results);
    printMarkdown(report, std::cout);
    if (!o.json_file.empty()) {
      std::ofstream json(o.json_file);
      writeJson(report, json);
      if (!json) throw std::runtime_error("cannot write " + o.json_file);
    }
    return report.lostIntegrations() == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "socc-loadtest: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  socc::keepHeapForLargeMessages();
  CLI::App app{
      "socc-loadtest: N simulated robots integrate KITTI-size scans and fetch chunks at a fixed "
      "rate against map_server; prints throughput, latency percentiles and lost integrations"};
  app.set_version_flag("--version", socc::versionLine("socc-loadtest"));
  Options o;
  addOptions(app, o);
  CLI11_PARSE(app, argc, argv);

  if (const std::string why = socc::checkLcmUrl(o.lcm_url);
      !why.empty() || o.lcm_url.rfind("udpm://", 0) != 0) {
    std::cerr << "socc-loadtest: --lcm-url: " << (why.empty() ? "must be udpm://" : why) << '\n';
    return 2;
  }
  return run(std::move(o));
}
