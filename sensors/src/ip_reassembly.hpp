#pragma once
// Reassembles fragmented IPv4 datagrams (RFC 791) for the pcap reader: a bounded number of
// datagrams in flight; incomplete ones are given up after a second or when the table is full
// (counted).
#include <cstdint>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

namespace socc::sensors {

class IpReassembly {
 public:
  struct Fragment {
    std::uint32_t source = 0, destination = 0;
    std::uint16_t id = 0;
    std::uint8_t protocol = 0;
    std::uint32_t offset = 0;  // bytes
    bool more = false;         // MF flag
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
    std::int64_t time_ns = 0;
  };

  /// Adds a fragment; returns the whole datagram's payload (the IP payload) when complete.
  std::optional<std::vector<std::uint8_t>> add(const Fragment& f);
  /// End of input: datagrams still waiting for fragments are given up.
  void finish() {
    abandoned_ += pending_.size();
    pending_.clear();
  }
  /// Datagrams given up so far (lost fragments, table full, overlapping or oversized pieces).
  std::uint64_t abandoned() const { return abandoned_; }

 private:
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint16_t, std::uint8_t>;
  struct Pending {
    std::vector<std::uint8_t> bytes;
    std::vector<bool> have;   // per 8-byte unit
    std::uint32_t total = 0;  // known once the last fragment arrived
    std::int64_t first_ns = 0;
  };
  void expire(std::int64_t now_ns);

  std::map<Key, Pending> pending_;
  std::uint64_t abandoned_ = 0;
};

}  // namespace socc::sensors
