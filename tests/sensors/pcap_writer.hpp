#pragma once
// Writes test captures with libpcap's own writer: Ethernet / IPv4 / UDP frames, optionally
// with an 802.1Q tag, and IPv4 fragments of large datagrams.
#include <pcap/pcap.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace socc::sensors::test {

class PcapWriter {
 public:
  explicit PcapWriter(const std::filesystem::path& file) {
    dead_ = pcap_open_dead_with_tstamp_precision(DLT_EN10MB, 65535, PCAP_TSTAMP_PRECISION_NANO);
    dumper_ = pcap_dump_open(dead_, file.c_str());
    if (dumper_ == nullptr) throw std::runtime_error("cannot write " + file.string());
  }
  ~PcapWriter() {
    pcap_dump_close(dumper_);
    pcap_close(dead_);
  }
  PcapWriter(const PcapWriter&) = delete;
  PcapWriter& operator=(const PcapWriter&) = delete;

  /// One UDP datagram, split into IPv4 fragments of at most mtu bytes of IP payload (a multiple
  /// of 8) when it does not fit; skip_fragment drops one of them (-1: none).
  void udp(std::int64_t stamp_ns, const std::vector<std::uint8_t>& payload, std::uint16_t dst_port,
           std::uint32_t src_ip = 0xC0A801C9, bool vlan = false, std::size_t mtu = 65000,
           int skip_fragment = -1) {
    std::vector<std::uint8_t> udp(8 + payload.size());
    be16(udp, 0, 2368);
    be16(udp, 2, dst_port);
    be16(udp, 4, static_cast<std::uint16_t>(udp.size()));
    std::copy(payload.begin(), payload.end(), udp.begin() + 8);
    const std::size_t step = udp.size() <= mtu ? udp.size() : (mtu / 8) * 8;
    int index = 0;
    for (std::size_t off = 0; off < udp.size(); off += step, ++index) {
      const std::size_t n = std::min(step, udp.size() - off);
      const bool more = off + n < udp.size();
      if (index != skip_fragment) frame(stamp_ns, udp, off, n, more, src_ip, vlan);
    }
    ++ip_id_;
  }

 private:
  static void be16(std::vector<std::uint8_t>& d, std::size_t at, std::uint16_t v) {
    d[at] = static_cast<std::uint8_t>(v >> 8);
    d[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
  }
  void frame(std::int64_t stamp_ns, const std::vector<std::uint8_t>& udp, std::size_t off,
             std::size_t n, bool more, std::uint32_t src_ip, bool vlan) {
    std::vector<std::uint8_t> f(14 + (vlan ? 4 : 0) + 20 + n, 0);
    std::size_t at = 12;
    if (vlan) {
      be16(f, at, 0x8100);
      be16(f, at + 2, 7);
      at += 4;
    }
    be16(f, at, 0x0800);
    at += 2;
    f[at] = 0x45;
    be16(f, at + 2, static_cast<std::uint16_t>(20 + n));
    be16(f, at + 4, ip_id_);
    be16(f, at + 6, static_cast<std::uint16_t>((more ? 0x2000 : 0) | (off / 8)));
    f[at + 8] = 64;
    f[at + 9] = 17;
    for (int i = 0; i < 4; ++i) f[at + 12 + i] = static_cast<std::uint8_t>(src_ip >> (24 - 8 * i));
    const std::uint32_t dst = 0xFFFFFFFF;
    for (int i = 0; i < 4; ++i) f[at + 16 + i] = static_cast<std::uint8_t>(dst >> (24 - 8 * i));
    std::copy(udp.begin() + static_cast<std::ptrdiff_t>(off),
              udp.begin() + static_cast<std::ptrdiff_t>(off + n),
              f.begin() + static_cast<std::ptrdiff_t>(at + 20));
    pcap_pkthdr h{};
    h.ts.tv_sec = stamp_ns / 1'000'000'000;
    h.ts.tv_usec =
        static_cast<suseconds_t>(stamp_ns % 1'000'000'000);  // nanoseconds (nano precision)
    h.caplen = h.len = static_cast<bpf_u_int32>(f.size());
    pcap_dump(reinterpret_cast<u_char*>(dumper_), &h, f.data());
  }

  pcap_t* dead_ = nullptr;
  pcap_dumper_t* dumper_ = nullptr;
  std::uint16_t ip_id_ = 1;
};

}  // namespace socc::sensors::test
