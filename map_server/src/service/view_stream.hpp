#pragma once
// The map's stream for live views (SOCC/MAP_DELTA, map_delta_t; socc-view): every period, the
// blocks whose occupied voxels changed since the last look, each sent once with its content
// at that moment (a block changed by many integrations in between is sent once), within a
// voxel budget per period; what does not fit stays pending. A block is sent only when a view
// would show the change: a voxel appeared or vanished, changed class, or its occupancy moved
// to another sixteenth (kOccupancyStep); re-observing a wall does not resend it. Alongside, a
// background refresh cycles through every block with a smaller budget, so a view that starts late
// (or lost a multicast message) fills in. Transport-free: the caller publishes the messages. Not
// thread-safe: called from the server's single thread, between requests.
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <vector>

#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/map_delta_t.hpp"

namespace socc::service {

/// Occupancy changes smaller than this (in round(p_occ * 255) units) are not sent as changes.
inline constexpr int kOccupancyStep = 16;

struct ViewStreamBudget {
  std::size_t changed_voxels = 65536;  // per period, changed blocks (at least one block)
  std::size_t refresh_voxels = 8192;   // per period, the background refresh
  std::size_t message_voxels = 32768;  // per message: splits a period's voxels (UDP loss)
};

class ViewStream {
 public:
  explicit ViewStream(ViewStreamBudget budget = {}) : budget_(budget) {}

  /// The messages of one period (empty when nothing changed and the map is empty).
  std::vector<map_delta_t> next(const map::SemanticOccupancyMap& map, std::int64_t utime);

  std::size_t pendingBlocks() const { return pending_.size(); }

 private:
  using Key = std::array<std::int32_t, 3>;
  /// Up to `budget` voxels of blocks taken from the front of keys, as messages of `kind`.
  void emit(const map::SemanticOccupancyMap& map, std::deque<Key>& keys, std::size_t budget,
            std::int8_t kind, std::int64_t utime, std::vector<map_delta_t>& out);

  ViewStreamBudget budget_;
  std::int64_t epoch_ = 0;
  std::int64_t seen_version_ = -1;  // blocks changed after it are not yet pending
  std::deque<Key> pending_;         // changed blocks to send, oldest first
  std::set<Key> pending_set_;       // the same keys, to coalesce repeated changes
  std::deque<Key> refresh_;         // the rest of the current refresh cycle
  struct Sent {
    std::uint64_t fingerprint = 0;  // of the block's content as last sent
    std::int64_t cycle = -1;        // the refresh cycle it was last sent in
  };
  std::map<Key, Sent> sent_;
  std::int64_t cycle_ = 0;  // refresh cycles begun
};

}  // namespace socc::service
