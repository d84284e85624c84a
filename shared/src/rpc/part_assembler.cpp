#include "socc/rpc/part_assembler.hpp"

#include <algorithm>

namespace socc::rpc {
namespace {

constexpr std::size_t kCompletedRemembered = 256;
constexpr std::size_t kMaxMissingPerNack = 1000;  // keeps a NACK within one IP packet or so

}  // namespace

bool PartAssembler::fits(const part_t& part, const Transfer* transfer) const {
  if (part.count <= 0 || part.index < 0 || part.index >= part.count || part.size < 0 ||
      part.offset < 0 || part.total_size <= 0 || part.total_size > limits_.max_message_bytes ||
      part.count > part.total_size || part.size > part.total_size - part.offset ||
      part.size != static_cast<std::int32_t>(part.data.size()))
    return false;
  return transfer == nullptr ||
         (transfer->have.size() == static_cast<std::size_t>(part.count) &&
          transfer->bytes.size() == static_cast<std::size_t>(part.total_size));
}

PartAssembler::Transfer& PartAssembler::open(const Key& key, const part_t& part) {
  if (transfers_.size() >= limits_.max_transfers) {
    // Drop the transfer that has waited longest for a part.
    const auto oldest = std::min_element(
        transfers_.begin(), transfers_.end(),
        [](auto& a, auto& b) { return a.second.last_activity < b.second.last_activity; });
    transfers_.erase(oldest);
  }
  Transfer& t = transfers_[key];
  t.bytes.assign(static_cast<std::size_t>(part.total_size), 0);
  t.have.assign(static_cast<std::size_t>(part.count), false);
  t.missing = part.count;
  return t;
}

std::optional<std::vector<std::uint8_t>> PartAssembler::add(const part_t& part,
                                                            Clock::time_point now) {
  const Key key{part.sender, part.transfer_id};
  if (completed_.count(key) != 0) return std::nullopt;
  auto it = transfers_.find(key);
  if (!fits(part, it == transfers_.end() ? nullptr : &it->second)) return std::nullopt;
  Transfer& t = it == transfers_.end() ? open(key, part) : it->second;
  t.last_activity = now;
  const auto index = static_cast<std::size_t>(part.index);
  if (t.have[index]) return std::nullopt;
  std::copy(part.data.begin(), part.data.end(), t.bytes.begin() + part.offset);
  t.have[index] = true;
  if (--t.missing > 0) return std::nullopt;
  std::vector<std::uint8_t> whole = std::move(t.bytes);
  transfers_.erase(key);
  rememberCompleted(key);
  return whole;
}

void PartAssembler::rememberCompleted(const Key& key) {
  completed_.insert(key);
  completed_order_.push_back(key);
  if (completed_order_.size() <= kCompletedRemembered) return;
  completed_.erase(completed_order_.front());
  completed_order_.pop_front();
}

std::vector<PartAssembler::Nack> PartAssembler::stalled(Clock::time_point now) {
  std::vector<Nack> nacks;
  for (auto it = transfers_.begin(); it != transfers_.end();) {
    Transfer& t = it->second;
    if (now - t.last_activity < limits_.stall) {
      ++it;
      continue;
    }
    if (t.nacks >= limits_.max_nacks) {
      it = transfers_.erase(it);
      continue;
    }
    Nack n{it->first.first, part_nack_t{}};
    n.nack.transfer_id = it->first.second;
    for (std::size_t i = 0; i < t.have.size() && n.nack.missing.size() < kMaxMissingPerNack; ++i)
      if (!t.have[i]) n.nack.missing.push_back(static_cast<std::int32_t>(i));
    n.nack.num_missing = static_cast<std::int32_t>(n.nack.missing.size());
    nacks.push_back(std::move(n));
    t.last_activity = now;
    ++t.nacks;
    ++it;
  }
  return nacks;
}

}  // namespace socc::rpc
