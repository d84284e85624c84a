// Capture files through libpcap; this file only peels the link, IPv4 and UDP headers.
#include "socc/sensors/pcap_source.hpp"

#include <pcap/pcap.h>

#include <array>
#include <fstream>
#include <stdexcept>
#include <string>

#include "ip_reassembly.hpp"

namespace socc::sensors {
namespace {

std::uint16_t be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}
std::uint32_t be32(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
         (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
}

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherVlan = 0x8100;
constexpr std::uint16_t kEtherQinQ = 0x88A8;
constexpr std::uint8_t kProtoUdp = 17;

class PcapSource final : public PacketSource {
 public:
  PcapSource(const std::filesystem::path& file, std::uint16_t port)
      : file_(file.string()), port_(port) {
    std::array<char, PCAP_ERRBUF_SIZE> err{};
    handle_ = pcap_open_offline_with_tstamp_precision(file_.c_str(), PCAP_TSTAMP_PRECISION_NANO,
                                                      err.data());
    if (handle_ == nullptr)
      throw std::runtime_error(file_ + ": not a readable pcap capture (" + err.data() + ")");
    link_ = pcap_datalink(handle_);
    if (link_ != DLT_EN10MB && link_ != DLT_LINUX_SLL && link_ != DLT_RAW && link_ != DLT_IPV4 &&
        link_ != DLT_NULL && link_ != DLT_LOOP) {
      const std::string name =
          pcap_datalink_val_to_name(link_) ? pcap_datalink_val_to_name(link_) : "?";
      pcap_close(handle_);
      throw std::runtime_error(file_ + ": link type " + name +
                               " is not supported (Ethernet, Linux cooked, raw IP)");
    }
  }
  ~PcapSource() override { pcap_close(handle_); }
  PcapSource(const PcapSource&) = delete;
  PcapSource& operator=(const PcapSource&) = delete;

  std::optional<Packet> next() override {
    while (!done_) {
      pcap_pkthdr* header = nullptr;
      const u_char* bytes = nullptr;
      const int rc = pcap_next_ex(handle_, &header, &bytes);
      if (rc == PCAP_ERROR_BREAK) {
        done_ = true;
        reassembly_.finish();
        break;
      }
      if (rc != 1) {  // a damaged or cut-off file: what was read stays valid
        damaged_ = std::string("the capture ends in a damaged record after ") +
                   std::to_string(records_) + " records (" + pcap_geterr(handle_) + ")";
        done_ = true;
        break;
      }
      ++records_;
      if (header->caplen < header->len) ++truncated_;
      const std::int64_t stamp = static_cast<std::int64_t>(header->ts.tv_sec) * 1'000'000'000 +
                                 static_cast<std::int64_t>(header->ts.tv_usec);
      if (std::optional<Packet> p = parse(bytes, header->caplen, stamp)) return p;
    }
    return std::nullopt;
  }

  std::string problems() const override {
    std::string s;
    if (!damaged_.empty()) s += file_ + ": " + damaged_ + "\n";
    if (truncated_ > 0)
      s += file_ + ": " + std::to_string(truncated_) +
           " records cut short by the capture's snap length\n";
    if (reassembly_.abandoned() > 0)
      s += file_ + ": " + std::to_string(reassembly_.abandoned()) +
           " fragmented datagrams incomplete (dropped)\n";
    return s;
  }

 private:
  // Returns the offset of the IPv4 header within the record, or -1 when it is not IPv4.
  long ipOffset(const std::uint8_t* d, std::size_t n) const {
    switch (link_) {
      case DLT_EN10MB: {
        std::size_t off = 12;
        if (n < off + 2) return -1;
        std::uint16_t type = be16(d + off);
        while ((type == kEtherVlan || type == kEtherQinQ) && n >= off + 6) {
          off += 4;
          type = be16(d + off);
        }
        return type == kEtherIpv4 ? static_cast<long>(off + 2) : -1;
      }
      case DLT_LINUX_SLL:
        return n >= 16 && be16(d + 14) == kEtherIpv4 ? 16 : -1;
      case DLT_NULL:
      case DLT_LOOP:
        return n >= 4 ? 4 : -1;
      default:
        return 0;  // raw IP
    }
  }

  std::optional<Packet> parse(const std::uint8_t* d, std::size_t n, std::int64_t stamp) {
    const long ip_at = ipOffset(d, n);
    if (ip_at < 0) return std::nullopt;
    const std::uint8_t* ip = d + ip_at;
    const std::size_t avail = n - static_cast<std::size_t>(ip_at);
    if (avail < 20 || (ip[0] >> 4) != 4) return std::nullopt;
    const std::size_t ihl = static_cast<std::size_t>(ip[0] & 0x0F) * 4;
    const std::size_t total = be16(ip + 2);
    if (ihl < 20 || total < ihl || ip[9] != kProtoUdp) return std::nullopt;
    if (total > avail) return std::nullopt;  // cut short: counted as truncated
    const std::uint16_t frag = be16(ip + 6);
    const bool more = (frag & 0x2000) != 0;
    const std::uint32_t offset = static_cast<std::uint32_t>(frag & 0x1FFF) * 8;
    std::vector<std::uint8_t> whole;
    const std::uint8_t* udp = ip + ihl;
    std::size_t udp_size = total - ihl;
    if (more || offset != 0) {
      std::optional<std::vector<std::uint8_t>> r = reassembly_.add(
          {be32(ip + 12), be32(ip + 16), be16(ip + 4), ip[9], offset, more, udp, udp_size, stamp});
      if (!r) return std::nullopt;
      whole = std::move(*r);
      udp = whole.data();
      udp_size = whole.size();
    }
    if (udp_size < 8) return std::nullopt;
    const std::size_t udp_len = be16(udp + 4);
    if (udp_len < 8 || udp_len > udp_size) return std::nullopt;
    Packet p;
    p.destination_port = be16(udp + 2);
    if (port_ != 0 && p.destination_port != port_) return std::nullopt;
    p.stamp_ns = stamp;
    p.source_ipv4 = be32(ip + 12);
    p.source_port = be16(udp);
    p.data.assign(udp + 8, udp + udp_len);
    return p;
  }

  std::string file_;
  std::uint16_t port_;
  pcap_t* handle_ = nullptr;
  int link_ = 0;
  bool done_ = false;
  std::uint64_t records_ = 0;
  std::uint64_t truncated_ = 0;
  std::string damaged_;
  IpReassembly reassembly_;
};

}  // namespace

std::unique_ptr<PacketSource> openPcap(const std::filesystem::path& file, std::uint16_t port) {
  return std::make_unique<PcapSource>(file, port);
}

bool isPcap(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<unsigned char, 4> m{};
  if (!in.read(reinterpret_cast<char*>(m.data()), 4)) return false;
  const std::uint32_t magic = be32(m.data());
  return magic == 0xA1B2C3D4 || magic == 0xD4C3B2A1 || magic == 0xA1B23C4D || magic == 0x4D3CB2A1 ||
         magic == 0x0A0D0D0A;
}

}  // namespace socc::sensors
