#include "ip_reassembly.hpp"

#include <algorithm>

namespace socc::sensors {
namespace {
constexpr std::size_t kMaxPending = 64;
constexpr std::int64_t kTimeoutNs = 1'000'000'000;
constexpr std::uint32_t kMaxIpDatagram = 65535;
}  // namespace

void IpReassembly::expire(std::int64_t now_ns) {
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (now_ns - it->second.first_ns > kTimeoutNs || now_ns < it->second.first_ns) {
      it = pending_.erase(it);
      ++abandoned_;
    } else {
      ++it;
    }
  }
}

std::optional<std::vector<std::uint8_t>> IpReassembly::add(const Fragment& f) {
  expire(f.time_ns);
  const std::uint32_t end = f.offset + static_cast<std::uint32_t>(f.size);
  const Key key{f.source, f.destination, f.id, f.protocol};
  if (end > kMaxIpDatagram || (f.more && f.size % 8 != 0)) {
    if (pending_.erase(key) > 0) ++abandoned_;
    ++abandoned_;
    return std::nullopt;
  }
  auto it = pending_.find(key);
  if (it == pending_.end()) {
    if (pending_.size() >= kMaxPending) {
      pending_.erase(pending_.begin());
      ++abandoned_;
    }
    it = pending_.emplace(key, Pending{}).first;
    it->second.first_ns = f.time_ns;
  }
  Pending& p = it->second;
  if (p.bytes.size() < end) {
    p.bytes.resize(end);
    p.have.resize((end + 7) / 8, false);
  }
  std::copy(f.data, f.data + f.size, p.bytes.begin() + f.offset);
  for (std::uint32_t u = f.offset / 8; u < (end + 7) / 8; ++u) p.have[u] = true;
  if (!f.more) p.total = end;
  if (p.total == 0 || p.bytes.size() != p.total) return std::nullopt;
  if (!std::all_of(p.have.begin(), p.have.end(), [](bool b) { return b; })) return std::nullopt;
  std::vector<std::uint8_t> whole = std::move(p.bytes);
  pending_.erase(it);
  return whole;
}

}  // namespace socc::sensors
