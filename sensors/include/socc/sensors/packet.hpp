#pragma once
// A LiDAR's UDP payload as a transport delivered it (pcap record, live socket, bag message),
// and the interface of everything that delivers packets. Decoders (scan_decoder.hpp) turn
// packets into scans; transports never interpret the payload.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace socc::sensors {

struct Packet {
  std::int64_t stamp_ns = 0;      // capture / receive / message time [ns, the recording's clock]
  std::uint32_t source_ipv4 = 0;  // sender (host byte order); 0 = unknown (bags)
  std::uint16_t source_port = 0;  // 0 = unknown
  std::uint16_t destination_port = 0;  // 0 = unknown (bags)
  std::vector<std::uint8_t> data;      // the UDP payload
};

class PacketSource {
 public:
  virtual ~PacketSource() = default;
  /// The next packet, or nullopt at the end of the recording (or after a live source's idle
  /// timeout). Throws std::runtime_error naming the file on a container it cannot read at all;
  /// damage after a valid start is counted (stats) and reading stops or resynchronises.
  virtual std::optional<Packet> next() = 0;
  /// What went wrong so far, for the run's summary ("3 truncated records"); empty when nothing.
  virtual std::string problems() const { return {}; }
};

}  // namespace socc::sensors
