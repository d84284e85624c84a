#pragma once
// Receiving side of large messages split into parts (part_t, docs/fleet.md "Large messages"):
// collects the parts of each transfer in any order, ignores duplicates and parts of transfers
// it already completed, reports which parts of a stalled transfer are missing, and gives up on
// a transfer after a number of unanswered requests for them. Pure logic (no LCM, no clock of
// its own): PartTransport feeds it. Memory is bounded: at most max_transfers incomplete
// transfers of at most max_message_bytes each (the oldest is dropped for a new one).
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "socc/part_nack_t.hpp"
#include "socc/part_t.hpp"

namespace socc::rpc {

struct PartAssemblerLimits {
  std::int32_t max_message_bytes = 64 << 20;
  std::size_t max_transfers = 32;
  std::chrono::milliseconds stall{20};  // no new part for this long: ask for the missing ones
  int max_nacks = 25;                   // then give up (the RPC retry sends it again)
};

class PartAssembler {
 public:
  using Clock = std::chrono::steady_clock;
  explicit PartAssembler(PartAssemblerLimits limits = {}) : limits_(limits) {}

  /// Adds a part received at now; returns the whole message when this part completed it.
  std::optional<std::vector<std::uint8_t>> add(const part_t& part, Clock::time_point now);

  /// A request for the missing parts of one stalled transfer, to publish to its sender.
  struct Nack {
    std::string sender;
    part_nack_t nack;
  };
  /// Stalled transfers at now (each at most once per stall period); drops those that were
  /// asked for max_nacks times.
  std::vector<Nack> stalled(Clock::time_point now);

  std::size_t incompleteTransfers() const { return transfers_.size(); }

 private:
  using Key = std::pair<std::string, std::int64_t>;  // sender, transfer id
  struct Transfer {
    std::vector<std::uint8_t> bytes;
    std::vector<bool> have;
    std::int32_t missing = 0;
    Clock::time_point last_activity;
    int nacks = 0;
  };
  bool fits(const part_t& part, const Transfer* transfer) const;
  Transfer& open(const Key& key, const part_t& part);
  void rememberCompleted(const Key& key);

  PartAssemblerLimits limits_;
  std::map<Key, Transfer> transfers_;
  // Recently completed transfers (oldest first): their late or repeated parts are ignored.
  std::deque<Key> completed_order_;
  std::set<Key> completed_;
};

}  // namespace socc::rpc
