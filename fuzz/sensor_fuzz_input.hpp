#pragma once
// Fuzz input of the packet decoders: a selector byte (which configuration), then packets, each
// a 2-byte little-endian length followed by that many bytes (cut at the end of the input).
// Decoded scans are checked: a decoder may drop or refuse input, never emit garbage.
#include <cmath>
#include <cstdint>
#include <vector>

#include "socc/sensors/packet.hpp"
#include "socc/sensors/scan_decoder.hpp"

namespace socc::fuzz {

inline std::vector<sensors::Packet> splitPackets(const std::uint8_t* data, std::size_t size) {
  std::vector<sensors::Packet> packets;
  std::size_t at = 0;
  std::int64_t stamp = 1'000'000'000;
  while (at + 2 <= size) {
    std::size_t n = data[at] | (data[at + 1] << 8);
    at += 2;
    if (n > size - at) n = size - at;
    sensors::Packet p;
    p.stamp_ns = stamp += 500'000;
    p.data.assign(data + at, data + at + n);
    packets.push_back(std::move(p));
    at += n;
  }
  return packets;
}

/// Traps (a fuzzer finding) on a scan with inconsistent or non-finite content.
inline void checkScans(const std::vector<sensors::SensorScan>& scans, std::size_t max_ring) {
  for (const auto& s : scans) {
    const std::size_t n = s.points.size();
    if (s.time.size() != n || s.intensity.size() != n || s.ring.size() != n ||
        s.return_index.size() != n)
      __builtin_trap();
    for (std::size_t i = 0; i < n; ++i) {
      if (!s.points[i].allFinite() || !std::isfinite(s.time[i]) || s.time[i] < 0.f ||
          s.time[i] > 10.f || s.ring[i] >= max_ring || s.return_index[i] > 1 ||
          s.points[i].norm() > 1000.f)
        __builtin_trap();
    }
  }
}

/// Feeds every packet, then flushes; scans are checked.
inline void decodeAll(sensors::ScanDecoder& decoder, const std::vector<sensors::Packet>& packets,
                      std::size_t max_ring) {
  std::vector<sensors::SensorScan> scans;
  for (const auto& p : packets) decoder.feed(p, scans);
  decoder.flush(scans);
  checkScans(scans, max_ring);
}

}  // namespace socc::fuzz
