#include "socc/auth/replay_guard.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace socc::auth {

CounterCheck ReplayGuard::check(const std::string& client_id, std::int64_t counter) const {
  const auto it = last_.find(client_id);
  if (it == last_.end() || counter > it->second) return CounterCheck::kFresh;
  return counter == it->second ? CounterCheck::kReplayed : CounterCheck::kStale;
}

void ReplayGuard::accept(const std::string& client_id, std::int64_t counter) {
  auto [it, inserted] = last_.emplace(client_id, counter);
  if (!inserted) it->second = std::max(it->second, counter);
}

void ReplayGuard::importCounters(const Counters& counters) {
  for (const auto& [id, counter] : counters) accept(id, counter);
}

std::string serializeCounters(const ReplayGuard::Counters& counters) {
  std::ostringstream out;
  for (const auto& [id, counter] : counters) {
    if (id.find('\n') != std::string::npos)
      throw std::invalid_argument("client id with a newline cannot be serialized");
    out << counter << ' ' << id << '\n';
  }
  return out.str();
}

ReplayGuard::Counters parseCounters(const std::string& text) {
  ReplayGuard::Counters counters;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const auto space = line.find(' ');
    std::size_t used = 0;
    std::int64_t counter = 0;
    try {
      if (space == std::string::npos) throw std::invalid_argument("no space");
      counter = std::stoll(line.substr(0, space), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != space)
      throw std::runtime_error("auth counters line " + std::to_string(n) +
                               ": expected '<counter> <client_id>'");
    const std::string id = line.substr(space + 1);
    auto [it, inserted] = counters.emplace(id, counter);
    if (!inserted) it->second = std::max(it->second, counter);
  }
  return counters;
}

}  // namespace socc::auth
