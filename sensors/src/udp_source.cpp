// Live UDP reception: one socket, poll() for the idle timeout, recvmsg() for the kernel's
// receive time stamp and its count of datagrams dropped for a full buffer (SO_RXQ_OVFL).
#include "socc/sensors/udp_source.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace socc::sensors {
namespace {

constexpr std::size_t kMaxUdpPayload = 65536;

[[noreturn]] void failWith(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

in_addr parseAddress(const std::string& text, const char* what) {
  in_addr a{};
  if (inet_pton(AF_INET, text.c_str(), &a) != 1)
    throw std::runtime_error(std::string(what) + " '" + text + "' is not an IPv4 address");
  return a;
}

in_addr interfaceAddress(const std::string& name) {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) failWith("getifaddrs");
  in_addr found{};
  bool ok = false;
  for (ifaddrs* i = list; i != nullptr; i = i->ifa_next)
    if (i->ifa_addr != nullptr && i->ifa_addr->sa_family == AF_INET && name == i->ifa_name) {
      found = reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr;
      ok = true;
      break;
    }
  freeifaddrs(list);
  if (!ok)
    throw std::runtime_error("interface '" + name + "' has no IPv4 address (or does not exist)");
  return found;
}

class UdpSource final : public PacketSource {
 public:
  explicit UdpSource(const UdpOptions& o) : options_(o), buffer_(kMaxUdpPayload) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) failWith("socket");
    try {
      setUp();
    } catch (...) {
      ::close(fd_);
      throw;
    }
  }
  ~UdpSource() override { ::close(fd_); }
  UdpSource(const UdpSource&) = delete;
  UdpSource& operator=(const UdpSource&) = delete;

  std::optional<Packet> next() override {
    pollfd p{fd_, POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + options_.idle_timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() < 0) return std::nullopt;
      const int r = ::poll(&p, 1, static_cast<int>(left.count()));
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) failWith("poll");
      if (r == 0) return std::nullopt;
      if (std::optional<Packet> packet = receive()) return packet;
    }
  }

  std::string problems() const override {
    if (kernel_drops_ == 0) return {};
    return "udp port " + std::to_string(options_.port) + ": " + std::to_string(kernel_drops_) +
           " datagrams dropped by the kernel (receive buffer full: raise net.core.rmem_max)\n";
  }

 private:
  void setUp() {
    const int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
    ::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one);
    const int size = options_.receive_buffer_bytes;
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(options_.port);
    local.sin_addr = parseAddress(options_.address, "bind address");
    if (!options_.multicast_group.empty()) {
      ip_mreq join{};
      join.imr_multiaddr = parseAddress(options_.multicast_group, "multicast group");
      if (!IN_MULTICAST(ntohl(join.imr_multiaddr.s_addr)))
        throw std::runtime_error("'" + options_.multicast_group +
                                 "' is not a multicast group (224.0.0.0/4)");
      join.imr_interface = options_.interface.empty() ? in_addr{htonl(INADDR_ANY)}
                                                      : interfaceAddress(options_.interface);
      if (::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &join, sizeof join) != 0)
        failWith("joining multicast group " + options_.multicast_group);
    } else if (!options_.interface.empty()) {
      if (::setsockopt(fd_, SOL_SOCKET, SO_BINDTODEVICE, options_.interface.c_str(),
                       static_cast<socklen_t>(options_.interface.size())) != 0)
        failWith("binding to interface " + options_.interface +
                 " (needs CAP_NET_RAW; or give --address)");
    }
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0)
      failWith("binding UDP " + options_.address + ":" + std::to_string(options_.port));
  }

  std::optional<Packet> receive() {
    sockaddr_in from{};
    iovec iov{buffer_.data(), buffer_.size()};
    alignas(cmsghdr) char control[256];
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof from;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return std::nullopt;
      failWith("recvmsg");
    }
    Packet p;
    p.stamp_ns = -1;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        p.stamp_ns = static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t drops = 0;
        std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
        kernel_drops_ = drops;
      }
    }
    if (p.stamp_ns < 0)
      p.stamp_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
    p.source_ipv4 = ntohl(from.sin_addr.s_addr);
    p.source_port = ntohs(from.sin_port);
    p.destination_port = options_.port;
    p.data.assign(buffer_.begin(), buffer_.begin() + n);
    return p;
  }

  UdpOptions options_;
  int fd_ = -1;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t kernel_drops_ = 0;
};

}  // namespace

std::unique_ptr<PacketSource> openUdp(const UdpOptions& options) {
  return std::make_unique<UdpSource>(options);
}

}  // namespace socc::sensors
