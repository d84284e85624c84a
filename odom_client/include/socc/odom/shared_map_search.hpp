#pragma once
// The search of the shared map by a robot that maps in its own frame (odom_client --own-frame),
// off its scan loop: each search asks the server to LOCALIZE (seconds on a large map) while the
// robot goes on registering its scans in its own frame. One search at a time, in a worker
// thread; the Relocalizer's followed places are touched by that thread only while it runs.
#include <Eigen/Geometry>
#include <cstdint>
#include <future>
#include <optional>

#include "socc/odom/odom_config.hpp"
#include "socc/odom/relocalizer.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::odom {

/// A finished search, with the own-frame frame it searched for.
struct SearchOutcome {
  Relocalization found;  // found.pose: the frame's pose in the shared map
  std::int64_t seq = 0;
  Eigen::Isometry3d own_pose = Eigen::Isometry3d::Identity();  // the frame's own-frame pose
  bool looked_back = false;  // a kept scan's search (KeptPlaceSweep), not the newest scans'
};

class SharedMapSearch {
 public:
  /// client must outlive this (MapClient calls may come from several threads).
  SharedMapSearch(const OdomConfig& config, rpc::MapClient& client);
  SharedMapSearch(const SharedMapSearch&) = delete;
  SharedMapSearch& operator=(const SharedMapSearch&) = delete;
  ~SharedMapSearch();  // waits for a running search

  bool running() const { return running_.valid(); }
  /// Starts a search of stacked (the newest scans in frame seq's frame, own-frame pose
  /// own_pose; motion: previous search's frame to this one). Not while one runs.
  void start(PreparedScan stacked, int scans, const Eigen::Isometry3d& motion,
             std::optional<PoseHint> hint, std::int64_t seq, const Eigen::Isometry3d& own_pose);
  /// The outcome once the running search has finished; nullopt while it runs or when none was
  /// started. Rethrows the search's failure (the map service failing after its retries; a
  /// service that could not search now only ends that search without a place: MapBusy).
  std::optional<SearchOutcome> poll();
  /// Waits for the running search; its outcome (nullopt when none runs).
  std::optional<SearchOutcome> wait();

 private:
  OdomConfig config_;
  rpc::MapClient& client_;
  Relocalizer relocalizer_;
  std::future<SearchOutcome> running_;  // last member: destroyed (joined) first
};

}  // namespace socc::odom
