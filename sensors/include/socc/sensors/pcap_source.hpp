#pragma once
// LiDAR packets from a capture file (libpcap: classic pcap and pcapng; Ethernet with VLAN tags,
// Linux cooked, raw IPv4 and loopback link types; IPv4 / UDP). Fragmented IPv4 datagrams (e.g.
// Ouster's 8448-byte packets on a 1500-byte MTU) are reassembled. Packet::stamp_ns is the capture
// time of the record.
#include <cstdint>
#include <filesystem>
#include <memory>

#include "socc/sensors/packet.hpp"

namespace socc::sensors {

/// port: UDP destination port to keep; 0 keeps every UDP datagram (decoders skip what is not
/// theirs). Throws std::runtime_error naming the file when it is not a readable capture.
std::unique_ptr<PacketSource> openPcap(const std::filesystem::path& file, std::uint16_t port);

/// True when the file starts like a pcap or pcapng capture.
bool isPcap(const std::filesystem::path& file);

}  // namespace socc::sensors
