#pragma once
// Service state stored in the map snapshot's metadata blob: an LCM map_stats_t (robot states +
// the journal sequence the snapshot covers, so it stays inspectable with LCM), followed, when
// the server authenticates requests, by the replay counters as text (see encodeSnapshotMetadata).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "socc/auth/replay_guard.hpp"
#include "socc/robot_state_t.hpp"

namespace socc::service {

struct SnapshotMetadata {
  std::vector<robot_state_t> robots;
  std::int64_t journal_sequence = 0;  // accepted Integrates contained in the snapshot
  // Last accepted auth_counter per client, so a restored server still refuses replays.
  auth::ReplayGuard::Counters auth_counters;
};

/// Without auth counters the blob is exactly the map_stats_t encoding (older snapshots).
std::string encodeSnapshotMetadata(const SnapshotMetadata& metadata);
/// nullopt when the blob does not decode; an empty blob is a snapshot without service state.
std::optional<SnapshotMetadata> decodeSnapshotMetadata(const std::string& blob);

}  // namespace socc::service
