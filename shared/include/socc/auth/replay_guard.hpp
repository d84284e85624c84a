#pragma once
// Replay protection: remembers the last accepted auth_counter of every client id.
// A request is fresh only when its counter is strictly greater than that value.
#include <cstdint>
#include <map>
#include <string>

namespace socc::auth {

enum class CounterCheck { kFresh, kReplayed, kStale };

class ReplayGuard {
 public:
  using Counters = std::map<std::string, std::int64_t>;

  /// kReplayed when counter equals the last accepted one, kStale when lower.
  CounterCheck check(const std::string& client_id, std::int64_t counter) const;
  /// Records counter as the last accepted one (never lowers it).
  void accept(const std::string& client_id, std::int64_t counter);

  /// Export/import so a server can persist the state across restarts; import keeps the
  /// higher counter of each client.
  const Counters& counters() const { return last_; }
  void importCounters(const Counters& counters);

 private:
  Counters last_;
};

/// Text form of the counters, one "<counter> <client_id>" line each (client ids may not
/// contain newlines). parseCounters throws std::runtime_error on malformed text.
std::string serializeCounters(const ReplayGuard::Counters& counters);
ReplayGuard::Counters parseCounters(const std::string& text);

}  // namespace socc::auth
