#pragma once
// LiDAR packets from the network, as the sensor sends them: a UDP socket bound to an address and
// port, optionally joined to a multicast group on an interface. Packet::stamp_ns is the
// kernel's receive time (SO_TIMESTAMPNS, CLOCK_REALTIME).
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "socc/sensors/packet.hpp"

namespace socc::sensors {

struct UdpOptions {
  std::string address = "0.0.0.0";  // local address to bind (0.0.0.0: every interface)
  std::uint16_t port = 2368;        // Velodyne's default data port
  std::string multicast_group;      // e.g. 239.255.0.1; empty: unicast / broadcast
  std::string interface;            // interface name for the multicast join (empty: the default)
  std::chrono::milliseconds idle_timeout{2000};  // next() gives up after this long without data
  int receive_buffer_bytes = 32 << 20;  // asked of the kernel (capped by net.core.rmem_max)
};

/// Throws std::runtime_error with the reason when the socket cannot be set up (port in use,
/// unknown interface, bad address).
std::unique_ptr<PacketSource> openUdp(const UdpOptions& options);

}  // namespace socc::sensors
