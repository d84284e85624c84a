#pragma once
// The map service's handlers: one per request type, each turning a decoded request into a
// reply (status + payload). Transport-free (the RequestRouter does LCM), so the handlers are
// unit-tested directly. Owns the one grid, the robot states and the durability state.
// Not thread-safe: the router calls it from its single LCM thread.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <variant>

#include "consistency_service.hpp"
#include "global_localizer.hpp"
#include "journal.hpp"
#include "robot_corrections.hpp"
#include "robot_registry.hpp"
#include "service_config.hpp"
#include "socc/auth/replay_guard.hpp"
#include "socc/chunk_reply_t.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/integrate_reply_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/keyframes_reply_t.hpp"
#include "socc/keyframes_request_t.hpp"
#include "socc/localize_reply_t.hpp"
#include "socc/localize_request_t.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/map_command_reply_t.hpp"
#include "socc/map_command_request_t.hpp"
#include "socc/map_stats_t.hpp"
#include "socc/render_reply_t.hpp"
#include "socc/render_request_t.hpp"
#include "socc/robot_pose_reply_t.hpp"
#include "socc/robot_pose_request_t.hpp"
#include "socc/robot_status_reply_t.hpp"
#include "socc/robot_status_request_t.hpp"
#include "socc/stats_reply_t.hpp"
#include "socc/stats_request_t.hpp"
#include "status.hpp"

namespace socc::service {

/// Request counters kept by the router and reported in map_stats_t.
struct RequestCounters {
  std::int64_t requests = 0;
  std::int64_t rejected = 0;  // non-OK replies and undecodable messages
  std::int64_t auth_failures = 0;
  std::int64_t decode_failures = 0;
};

/// Where the service keeps its durable state (both optional; journal needs the snapshot).
struct Durability {
  std::optional<std::filesystem::path> snapshot_file;
  std::optional<std::filesystem::path> journal_file;
  bool show_progress = true;  // progress bar while replaying the journal (off with --quiet)
  JournalSync journal_sync = JournalSync::kBatch;  // --journal-sync
};

class MapService {
 public:
  explicit MapService(const ServerConfig& config);

  /// received/received_size: the bytes request was decoded from (all of them), journaled as
  /// they are; without them (in-process callers) the request is re-encoded for the journal.
  /// A known robot's request must pass admitIntegrate (plausibility.hpp) first.
  integrate_reply_t integrate(const integrate_request_t& request,
                              const std::uint8_t* received = nullptr,
                              std::size_t received_size = 0);
  chunk_reply_t getChunk(const chunk_request_t& request) const;
  stats_reply_t getStats(const stats_request_t& request, const RequestCounters& counters) const;
  robot_pose_reply_t getRobotPose(const robot_pose_request_t& request) const;
  /// GET_KEYFRAMES: the robot's keyframes with their optimized poses in the map frame
  /// (map_service_keyframes.cpp); FAILED_PRECONDITION without the consistency service.
  keyframes_reply_t getKeyframes(const keyframes_request_t& request) const;
  map_command_reply_t command(const map_command_request_t& request);
  render_reply_t render(const render_request_t& request) const;
  /// ROBOT_STATUS: stores the tracking state the robot (client_id) reports.
  robot_status_reply_t robotStatus(const robot_status_request_t& request);
  /// LOCALIZE: ranked candidate poses of a scan in the map (global_localizer.hpp). Read-only
  /// for the map; updates the descriptor cache. beginLocalize + search.run + finishLocalize.
  localize_reply_t localize(const localize_request_t& request);

  /// A LOCALIZE search between beginLocalize and finishLocalize (docs/relocalization.md,
  /// "Threading"): search.run() may go on on another thread while the service serves others.
  struct PendingLocalize {
    localization::LocalizeSearch search;
    localize_reply_t reply;  // map_version of the snapshot
    std::chrono::steady_clock::time_point start;
    std::exception_ptr error;  // what search.run threw

    /// search.run(cancel), its exception kept for finishLocalize. Touches no grid.
    void run(const std::atomic<bool>* cancel = nullptr);
  };
  /// The reply at once (a refused request, check mode) or the search to run. may_search false
  /// (the server's searches are all busy): a request that needs a search is refused with
  /// RESOURCE_EXHAUSTED.
  std::variant<localize_reply_t, PendingLocalize> beginLocalize(const localize_request_t& request,
                                                                bool may_search = true);
  /// The reply of a search that ran: its hypotheses ranked on the grid as it is now (INTERNAL
  /// when it threw; RESOURCE_EXHAUSTED, "try again", when another grid was swapped in since).
  localize_reply_t finishLocalize(PendingLocalize pending) const;

  map_stats_t stats(const RequestCounters& counters) const;
  const map::SemanticOccupancyMap& map() const { return map_; }
  const ServerConfig& config() const { return config_; }
  const RobotRegistry& robots() const { return robots_; }
  std::int64_t integrations() const { return integrations_; }
  /// The consistency service (docs/consistency.md); null unless config.consistency.enabled.
  consistency::ConsistencyService* consistency() { return consistency_.get(); }
  /// Grids rebuilt by the consistency service and swapped in (docs/consistency.md).
  std::int64_t mapCorrections() const { return map_corrections_; }

  // Durability -------------------------------------------------------------------------------
  /// Restores state: snapshot (if given) then replays the journal (if it exists), then starts
  /// journaling with a fresh checkpoint. Throws std::runtime_error with the reason on a
  /// corrupt snapshot or a journal that does not continue the snapshot.
  void openDurability(const Durability& durability,
                      const std::optional<std::filesystem::path>& restore_snapshot);
  /// Writes the snapshot (atomic) and restarts the journal after it. Returns voxels saved.
  std::int64_t checkpoint();
  /// True when INTEGRATE acknowledgements must wait for syncJournal() (journal in batch mode).
  bool acksWaitForSync() const;
  /// Forces the journaled integrations to stable storage (batch mode: once per group of
  /// requests, before their replies go out). Throws std::runtime_error when that fails.
  void syncJournal();
  const Journal* journal() const { return journal_.get(); }
  /// Loads a snapshot into the service (map + robot states); throws std::runtime_error.
  void loadSnapshot(const std::filesystem::path& file);
  void saveSnapshot(const std::filesystem::path& file) const;
  /// Applies journal entries not covered by the current state; returns how many were applied.
  std::int64_t replayJournal(const JournalContents& contents, bool show_progress);
  /// Persists guard's per-client auth counters in every snapshot and restores them (keeping the
  /// higher value) on load, so a restored server still refuses replays. guard must outlive
  /// the service; attach it before openDurability.
  void attachReplayGuard(auth::ReplayGuard& guard) { replay_guard_ = &guard; }

 private:
  /// No robot known and no voxel: a robot may found the map (integrate_request_t::FOUND_MAP).
  bool holdsNothing() const;
  /// judge: live requests pass admitIntegrate; journal replay does not (each entry passed it
  /// when it arrived, and the tracking reports since then are not journaled).
  Status applyIntegrate(const integrate_request_t& request, integrate_reply_t& reply, bool judge,
                        const std::uint8_t* received = nullptr, std::size_t received_size = 0);
  /// Room for a new robot; with judge, a known robot's request passes admitIntegrate (its
  /// refusals are counted in its state).
  Status admitRobot(const integrate_request_t& request, bool judge);
  Status runCommand(const map_command_request_t& request, map_command_reply_t& reply);
  double integrationsPerSecond() const;
  /// Swaps in the consistency service's rebuilt grid, if one is ready: the map version goes on
  /// from the old grid's (a new epoch: clients' cached chunks are stale), every robot it
  /// corrects is told with its next INTEGRATE, and the journal restarts after a checkpoint of it.
  void swapInRebuiltGrid();
  /// A new consistency service for a new grid (LOAD, CLEAR, a restored snapshot) with a new
  /// store: one that did not see the grid's scans estimates but never rebuilds it (it would
  /// drop them).
  void restartConsistency();
  // map_service_consistency.cpp: the consistency service's store beside the snapshot.
  /// After a restart from the snapshot file: the service as its store left it, when the store
  /// covers the snapshot; else restartConsistency() with the reason on stderr.
  void resumeConsistency();
  std::unique_ptr<consistency::KeyframeStore> newConsistencyStore(bool foreign_base) const;
  /// Maps the consistency service's graph frame into the map frame (map_service_keyframes.cpp).
  Eigen::Isometry3d graphToMap() const;
  std::optional<std::filesystem::path> consistencyStoreFile() const;

  ServerConfig config_;
  map::SemanticOccupancyMap map_;
  RobotRegistry robots_;
  std::int64_t integrations_ = 0;  // accepted Integrates ever: the journal sequence
  RobotCorrections corrections_;   // each robot's frame after map corrections
  std::int64_t map_corrections_ = 0;
  std::deque<std::chrono::steady_clock::time_point> recent_integrations_;  // rate window
  Durability durability_;
  std::unique_ptr<Journal> journal_;
  auth::ReplayGuard* replay_guard_ = nullptr;  // not owned (the AuthGate's); null without a key
  localization::GlobalLocalizer localizer_;
  bool consistency_foreign_ = false;  // the service began on a grid it did not see built
  std::unique_ptr<consistency::ConsistencyService>
      consistency_;  // last: its thread reads nothing else
};

}  // namespace socc::service
