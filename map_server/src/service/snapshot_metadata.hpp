#pragma once
// Service state stored in the map snapshot's metadata blob: an LCM map_stats_t (robot states +
// the journal sequence the snapshot covers, so it stays inspectable with LCM), then the robots'
// pose histories (a tagged section of pose_history_t messages) and, when the server
// authenticates requests, the replay counters as text (see encodeSnapshotMetadata); after a map
// correction, the robots' frames as text before them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "socc/auth/replay_guard.hpp"
#include "socc/pose_history_t.hpp"
#include "socc/robot_state_t.hpp"

namespace socc::service {

struct SnapshotMetadata {
  std::vector<robot_state_t> robots;
  std::vector<pose_history_t> histories;  // empty in snapshots written before pose histories
  std::int64_t journal_sequence = 0;      // accepted Integrates contained in the snapshot
  // Last accepted auth_counter per client, so a restored server still refuses replays.
  auth::ReplayGuard::Counters auth_counters;
  // The robots' frames after map corrections (RobotCorrections::serialize; empty: none).
  std::string corrections;
};

/// Without histories and auth counters the blob is exactly the map_stats_t encoding.
std::string encodeSnapshotMetadata(const SnapshotMetadata& metadata);
/// nullopt when the blob does not decode; an empty blob is a snapshot without service state.
std::optional<SnapshotMetadata> decodeSnapshotMetadata(const std::string& blob);

}  // namespace socc::service
