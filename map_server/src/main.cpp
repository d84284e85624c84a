// map_server: owns the one semantic occupancy grid and serves it over LCM
// (request/response services SOCC/<SERVICE>/REQ -> SOCC/<SERVICE>/REP/<client_id>, status on
// SOCC/STATUS). See map_server/README.md, section "Service".
#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "service/auth_gate.hpp"
#include "service/map_service.hpp"
#include "service/request_gate.hpp"
#include "service/request_router.hpp"
#include "service/service_config.hpp"
#include "service/view_stream.hpp"
#include "socc/channels.hpp"
#include "socc/large_message_heap.hpp"
#include "socc/lcm_url.hpp"
#include "socc/version.hpp"
#include "socc/wall_clock.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string lcm_url{socc::channels::kDefaultLcmUrl};
  std::string config_file;
  std::string restore;
  std::string snapshot_dir;
  double snapshot_period = 60.0;
  std::string journal;
  std::string journal_sync = "batch";
  std::string file_dir;
  std::string key_file;
  bool auth_queries = false;
  double status_period = 1.0;
  double view_period = 0.5;
  bool quiet = false;
  bool ignore_corrupt_snapshot = false;
  bool consistency = false;
  std::string consistency_dir;
};

// Moves a damaged durable file out of the way (never deletes it: it may be rescued by hand).
void setAside(const fs::path& file) {
  const fs::path aside = file.string() + ".corrupt-" + std::to_string(std::time(nullptr));
  std::error_code ec;
  fs::rename(file, aside, ec);
  std::cerr << "map_server: moved " << file << " to " << aside << '\n';
}

void restoreState(socc::service::MapService& service, const Options& options) {
  socc::service::Durability durability;
  if (!options.snapshot_dir.empty())
    durability.snapshot_file = fs::path(options.snapshot_dir) / "map.snap";
  if (!options.journal.empty()) durability.journal_file = options.journal;
  durability.journal_sync = *socc::service::parseJournalSync(options.journal_sync);
  durability.show_progress = !options.quiet;
  std::optional<fs::path> restore;
  if (!options.restore.empty()) restore = options.restore;
  try {
    service.openDurability(durability, restore);
  } catch (const std::exception& e) {
    if (!options.ignore_corrupt_snapshot) throw;
    std::cerr << "map_server: WARNING: " << e.what()
              << "\nmap_server: --ignore-corrupt-snapshot: starting with an empty map\n";
    if (restore && fs::exists(*restore)) setAside(*restore);
    if (durability.journal_file && fs::exists(*durability.journal_file))
      setAside(*durability.journal_file);
    service.openDurability(durability, std::nullopt);
  }
}

// AllowAllGate without a key, else an AuthGate whose counters the service persists in its
// snapshots (attached before any snapshot is restored). Throws on key file problems.
std::unique_ptr<socc::service::RequestGate> makeGate(const socc::service::ServerConfig& config,
                                                     socc::service::MapService& service) {
  if (config.key_file.empty()) return std::make_unique<socc::service::AllowAllGate>();
  auto gate = std::make_unique<socc::service::AuthGate>(
      socc::auth::SharedKey::fromFile(config.key_file), config.auth_queries);
  service.attachReplayGuard(gate->replayGuard());
  return gate;
}

// SIGINT/SIGTERM are blocked and polled, so shutdown happens between two requests and the
// final snapshot never races a handler. Called first thing: threads inherit the mask, and the
// integrator's TBB workers are created by the first integration, i.e. by a journal replay in
// restoreState(); a worker that did not block them took SIGTERM and killed the process without
// the final snapshot. A signal during the restore is handled once it has finished.
sigset_t blockStopSignals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  return stop_signals;
}

// --config with the command line's overrides; nullopt (after saying why) when they are invalid.
std::optional<socc::service::ServerConfig> serverConfig(const Options& options) {
  socc::service::ServerConfig config;
  try {
    if (!options.config_file.empty()) config = socc::service::loadServerConfig(options.config_file);
  } catch (const std::exception& e) {
    std::cerr << "map_server: bad config: " << e.what() << '\n';
    return std::nullopt;
  }
  if (!options.file_dir.empty()) config.file_dir = options.file_dir;
  if (!options.key_file.empty()) config.key_file = options.key_file;
  config.auth_queries = config.auth_queries || options.auth_queries;
  config.consistency.enabled = config.consistency.enabled || options.consistency ||
                               !options.consistency_dir.empty();
  const auto auth = socc::lcmAuthFor(config.key_file.string());
  if (const std::string why = socc::checkLcmUrl(options.lcm_url, auth); !why.empty()) {
    std::cerr << "map_server: " << why << '\n';
    return std::nullopt;
  }
  if (config.auth_queries && config.key_file.empty()) {
    std::cerr << "map_server: --auth-queries needs a key (--key-file or key_file: in --config)\n";
    return std::nullopt;
  }
  if (!options.journal.empty() && options.snapshot_dir.empty()) {
    std::cerr << "map_server: --journal needs --snapshot-dir (the journal restarts after each "
                 "snapshot)\n";
    return std::nullopt;
  }
  return config;
}

void announce(const Options& options, const socc::service::ServerConfig& config,
              const socc::service::MapService& service) {
  if (options.quiet) return;
  if (!config.key_file.empty())
    std::cerr << "map_server: requests must be signed (" << config.key_file.string() << "; "
              << (config.auth_queries ? "all services" : "state-changing services") << ")\n";
  std::cerr << "map_server: ready on " << options.lcm_url << " ("
            << service.map().stats().num_voxels << " voxels, " << service.robots().size()
            << " robots)\n";
}

// Handles the request that arrives within 10 ms and up to kMaxGroup more already waiting, then
// commits them (one journal sync for the group's INTEGRATEs, then their replies), asks for
// missing parts of stalled requests sent in parts and replies to the LOCALIZE searches that
// ended (router.poll()). Returns false when LCM fails.
bool handleGroup(lcm::LCM& lcm, socc::service::RequestRouter& router) {
  constexpr int kMaxGroup = 32;
  int handled = lcm.handleTimeout(10);
  if (handled < 0) return false;
  for (int n = 0; handled > 0 && n < kMaxGroup; ++n) {
    handled = lcm.handleTimeout(0);
    if (handled < 0) return false;
  }
  router.commit();
  router.poll();
  return true;
}

// Publishes the view stream's messages of one period on SOCC/MAP_DELTA.
void publishView(lcm::LCM& lcm, socc::service::ViewStream& view,
                 const socc::service::MapService& service) {
  for (socc::map_delta_t& delta : view.next(service.map(), socc::nowMicros())) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(delta.getEncodedSize()));
    delta.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    lcm.publish(std::string(socc::channels::kMapDelta), bytes.data(),
                static_cast<unsigned>(bytes.size()));
  }
}

// --consistency-dir: the consistency service's keyframes, closures and figures, once every
// keyframe received is processed.
void writeConsistency(socc::service::MapService& service, const Options& options) {
  socc::consistency::ConsistencyService* consistency = service.consistency();
  if (consistency == nullptr || options.consistency_dir.empty()) return;
  consistency->flush();
  try {
    consistency->write(options.consistency_dir);
  } catch (const std::exception& e) {
    std::cerr << "map_server: " << e.what() << '\n';
  }
}

// Handles requests until a stop signal, publishing the status and writing periodic snapshots
// in between. Returns 0, or 1 when LCM fails.
int serve(lcm::LCM& lcm, socc::service::RequestRouter& router, socc::service::MapService& service,
          const Options& options, const sigset_t& stop_signals) {
  const timespec no_wait{0, 0};
  const auto status_period = std::chrono::duration<double>(options.status_period);
  const auto snapshot_period = std::chrono::duration<double>(options.snapshot_period);
  const bool periodic_snapshots = !options.snapshot_dir.empty() && options.snapshot_period > 0;
  const auto view_period = std::chrono::duration<double>(options.view_period);
  socc::service::ViewStream view;
  auto next_status = Clock::now();
  auto next_view = Clock::now();
  auto next_snapshot = Clock::now() + snapshot_period;
  while (sigtimedwait(&stop_signals, nullptr, &no_wait) < 0) {
    if (!handleGroup(lcm, router)) {
      std::cerr << "map_server: LCM receive failed\n";
      return 1;
    }
    const auto now = Clock::now();
    if (options.status_period > 0 && now >= next_status) {
      router.publishStatus();
      next_status = now + std::chrono::duration_cast<Clock::duration>(status_period);
    }
    if (options.view_period > 0 && now >= next_view) {
      publishView(lcm, view, service);
      next_view = now + std::chrono::duration_cast<Clock::duration>(view_period);
    }
    if (periodic_snapshots && now >= next_snapshot) {
      try {
        service.checkpoint();
      } catch (const std::exception& e) {
        std::cerr << "map_server: snapshot failed (journal kept): " << e.what() << '\n';
      }
      next_snapshot = now + std::chrono::duration_cast<Clock::duration>(snapshot_period);
    }
  }
  return 0;
}

int run(const Options& options) {
  const sigset_t stop_signals = blockStopSignals();
  const std::optional<socc::service::ServerConfig> config = serverConfig(options);
  if (!config) return 2;
  if (!options.snapshot_dir.empty()) fs::create_directories(options.snapshot_dir);

  socc::service::MapService service(*config);
  std::unique_ptr<socc::service::RequestGate> gate;
  try {
    gate = makeGate(*config, service);
  } catch (const std::exception& e) {
    std::cerr << "map_server: " << e.what() << '\n';
    return 2;
  }
  try {
    restoreState(service, options);
  } catch (const std::exception& e) {
    std::cerr << "map_server: cannot restore: " << e.what()
              << "\n(use --ignore-corrupt-snapshot to start with an empty map instead)\n";
    return 1;
  }

  lcm::LCM lcm(options.lcm_url);
  if (!lcm.good()) {
    std::cerr << "map_server: cannot open LCM on " << options.lcm_url
              << " (multicast routed to lo? `ip route replace 224.0.0.0/4 dev lo`)\n";
    return 1;
  }
  socc::service::RequestRouter router(lcm, service, *gate, !options.quiet,
                                      socc::isLanLcmUrl(options.lcm_url));
  announce(options, *config, service);
  if (const int rc = serve(lcm, router, service, options, stop_signals); rc != 0) return rc;
  router.commit();
  if (!options.snapshot_dir.empty()) service.checkpoint();
  writeConsistency(service, options);
  if (!options.quiet) std::cerr << "map_server: stopped\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  socc::keepHeapForLargeMessages();
  CLI::App app{
      "map_server: the shared semantic occupancy grid, served over LCM.\n"
      "Services on SOCC/<SERVICE>/REQ (INTEGRATE, GET_CHUNK, GET_STATS, GET_ROBOT_POSE,\n"
      "MAP_COMMAND, RENDER, ROBOT_STATUS, LOCALIZE, GET_KEYFRAMES), replies on "
      "SOCC/<SERVICE>/REP/<client_id>, status on SOCC/STATUS."};
  app.set_version_flag("--version", socc::versionLine("map_server"));
  Options options;
  app.add_option("--lcm-url", options.lcm_url,
                 "LCM URL: udpm://239.x.y.z:port?ttl=0 (this machine) or memq://; ttl=1 (LAN, "
                 "docs/fleet.md) only with --key-file. Large GET_CHUNK replies need a big "
                 "receive buffer on the client: ...&recv_buf_size=67108864")
      ->capture_default_str();
  app.add_option("--config", options.config_file,
                 "server YAML (map_server/config/server.yaml); unknown keys are an error")
      ->check(CLI::ExistingFile);
  app.add_option("--restore", options.restore, "snapshot to restore at start");
  app.add_option("--snapshot-dir", options.snapshot_dir,
                 "directory for periodic snapshots (<dir>/map.snap, written atomically)");
  app.add_option("--snapshot-period", options.snapshot_period,
                 "seconds between periodic snapshots (0 = only at exit)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--journal", options.journal,
                 "write-ahead journal (LCM log) of accepted INTEGRATEs; replayed at start; "
                 "needs --snapshot-dir");
  app.add_option("--journal-sync", options.journal_sync,
                 "when journal entries reach stable storage (docs/fleet.md): always (fdatasync "
                 "per INTEGRATE before its reply), batch (one fdatasync per group of waiting "
                 "requests, replies after it), none (never: survives kill -9, not power loss)")
      ->capture_default_str()
      ->check(CLI::IsMember({"always", "batch", "none"}));
  app.add_option("--file-dir", options.file_dir,
                 "directory MAP_COMMAND paths are resolved in (overrides file_dir of --config)");
  app.add_option("--key-file", options.key_file,
                 "shared key (mode 0600, docs/security.md): INTEGRATE and MAP_COMMAND must then "
                 "be signed (overrides key_file of --config)");
  app.add_flag("--auth-queries", options.auth_queries,
               "with a key, also require signed GET_CHUNK, GET_STATS, GET_ROBOT_POSE, RENDER, "
               "LOCALIZE and GET_KEYFRAMES");
  app.add_option("--status-period", options.status_period,
                 "seconds between map_stats_t on SOCC/STATUS (0 = off)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--view-period", options.view_period,
                 "seconds between map_delta_t on SOCC/MAP_DELTA: changed blocks and a background "
                 "refresh for live views (socc-view, docs/view.md); 0 = off")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--quiet", options.quiet, "no log output except errors");
  app.add_flag("--ignore-corrupt-snapshot", options.ignore_corrupt_snapshot,
               "start with an empty map when the snapshot or journal cannot be restored "
               "(the damaged files are moved aside, not deleted)");
  app.add_flag("--consistency", options.consistency,
               "loop closure and robot-to-robot alignment over a pose graph of keyframes "
               "(docs/consistency.md; consistency.enabled of --config)");
  app.add_option("--consistency-dir", options.consistency_dir,
                 "with --consistency: write keyframes.txt (odometry and optimized poses), "
                 "closures.txt and stats.txt here at exit (implies --consistency)");
  CLI11_PARSE(app, argc, argv);

  try {
    return run(options);
  } catch (const std::exception& e) {
    std::cerr << "map_server: fatal: " << e.what() << '\n';
    return 1;
  }
}
