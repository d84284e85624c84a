// TEMPORARY test-only readers: see vendor_test_io.hpp.
#include "vendor_test_io.hpp"

#include <pcap/pcap.h>
#include <sqlite3.h>

#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace socc::sensors::test_io {
namespace {

std::uint16_t be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] << 8 | p[1]);
}
std::uint32_t be32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(be16(p)) << 16 | be16(p + 2);
}

// Fragments of one IPv4 datagram, by offset; complete when the last one arrived and no hole.
struct Datagram {
  std::map<std::size_t, std::vector<std::uint8_t>> pieces;
  std::size_t total = 0;  // known once the fragment without "more fragments" arrived

  bool complete() const {
    if (total == 0) return false;
    std::size_t next = 0;
    for (const auto& [offset, bytes] : pieces) {
      if (offset > next) return false;
      next = std::max(next, offset + bytes.size());
    }
    return next >= total;
  }
  std::vector<std::uint8_t> assemble() const {
    std::vector<std::uint8_t> out(total);
    for (const auto& [offset, bytes] : pieces)
      std::memcpy(out.data() + offset, bytes.data(), std::min(bytes.size(), total - offset));
    return out;
  }
};

// Offset of the IPv4 header in a captured frame, or -1 when the frame is not IPv4.
long ipv4Offset(int link, const std::uint8_t* d, std::size_t size) {
  if (link == DLT_RAW) return 0;
  if (link == DLT_LINUX_SLL) return size >= 16 && be16(d + 14) == 0x0800 ? 16 : -1;
  if (link != DLT_EN10MB || size < 14) return -1;
  std::size_t off = 12;
  std::uint16_t type = be16(d + off);
  while (type == 0x8100 && off + 6 <= size) {  // 802.1Q VLAN tags
    off += 4;
    type = be16(d + off);
  }
  return type == 0x0800 ? static_cast<long>(off + 2) : -1;
}

}  // namespace

std::vector<Packet> readPcapUdp(const std::filesystem::path& file, std::uint16_t port) {
  char error[PCAP_ERRBUF_SIZE] = {};
  std::unique_ptr<pcap_t, void (*)(pcap_t*)> pcap(pcap_open_offline(file.c_str(), error),
                                                  pcap_close);
  if (!pcap) throw std::runtime_error(file.string() + ": " + error);
  const int link = pcap_datalink(pcap.get());
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint16_t>, Datagram> partial;
  std::vector<Packet> out;
  pcap_pkthdr* header = nullptr;
  const u_char* frame = nullptr;
  while (pcap_next_ex(pcap.get(), &header, &frame) == 1) {
    const long ip = ipv4Offset(link, frame, header->caplen);
    if (ip < 0 || header->caplen < static_cast<std::size_t>(ip) + 20) continue;
    const std::uint8_t* h = frame + ip;
    const std::size_t ihl = (h[0] & 0x0f) * 4u;
    const std::size_t length = be16(h + 2);
    if ((h[0] >> 4) != 4 || h[9] != 17 || length < ihl ||
        header->caplen < static_cast<std::size_t>(ip) + length)
      continue;
    const std::uint16_t flags = be16(h + 6);
    const std::size_t frag_offset = (flags & 0x1fff) * 8u;
    const bool more = flags & 0x2000;
    const auto key = std::make_tuple(be32(h + 12), be32(h + 16), be16(h + 4));
    std::vector<std::uint8_t> datagram(h + ihl, h + length);
    if (more || frag_offset > 0) {
      Datagram& d = partial[key];
      if (!more) d.total = frag_offset + datagram.size();
      d.pieces[frag_offset] = std::move(datagram);
      if (!d.complete()) continue;
      datagram = d.assemble();
      partial.erase(key);
    }
    if (datagram.size() < 8 || be16(datagram.data() + 2) != port) continue;
    const std::size_t udp_length = be16(datagram.data() + 4);
    if (udp_length < 8 || udp_length > datagram.size()) continue;
    Packet p;
    p.stamp_ns = static_cast<std::int64_t>(header->ts.tv_sec) * 1'000'000'000 +
                 static_cast<std::int64_t>(header->ts.tv_usec) * 1000;
    p.source_ipv4 = std::get<0>(key);
    p.source_port = be16(datagram.data());
    p.destination_port = port;
    p.data.assign(datagram.begin() + 8, datagram.begin() + static_cast<long>(udp_length));
    out.push_back(std::move(p));
  }
  return out;
}

namespace {

// CDR (little-endian) reader; alignment counts from after the 4-byte encapsulation header.
class Cdr {
 public:
  Cdr(const std::uint8_t* data, std::size_t size) : d_(data), size_(size), pos_(4) {}
  std::uint32_t u32() {
    align(4);
    need(4);
    std::uint32_t v;
    std::memcpy(&v, d_ + pos_, 4);
    pos_ += 4;
    return v;
  }
  void skipString() { skip(u32()); }
  const std::uint8_t* bytes(std::size_t n) {
    need(n);
    const std::uint8_t* p = d_ + pos_;
    pos_ += n;
    return p;
  }
  void skip(std::size_t n) { bytes(n); }

 private:
  void align(std::size_t a) { pos_ = 4 + (pos_ - 4 + a - 1) / a * a; }
  void need(std::size_t n) const {
    if (pos_ + n > size_) throw std::runtime_error("PandarScan message truncated");
  }
  const std::uint8_t* d_;
  std::size_t size_, pos_;
};

}  // namespace

std::vector<std::vector<Packet>> readDb3PandarScans(const std::filesystem::path& file) {
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(file.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(raw);
    throw std::runtime_error(file.string() + ": cannot open");
  }
  std::unique_ptr<sqlite3, int (*)(sqlite3*)> db(raw, sqlite3_close);
  sqlite3_stmt* stmt_raw = nullptr;
  const char* sql =
      "SELECT m.data FROM messages m JOIN topics t ON m.topic_id = t.id "
      "WHERE t.type = 'pandar_msgs/msg/PandarScan' ORDER BY m.timestamp";
  if (sqlite3_prepare_v2(db.get(), sql, -1, &stmt_raw, nullptr) != SQLITE_OK)
    throw std::runtime_error(file.string() + ": " + sqlite3_errmsg(db.get()));
  std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)> stmt(stmt_raw, sqlite3_finalize);
  std::vector<std::vector<Packet>> scans;
  while (sqlite3_step(stmt.get()) == SQLITE_ROW) {
    Cdr cdr(static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt.get(), 0)),
            static_cast<std::size_t>(sqlite3_column_bytes(stmt.get(), 0)));
    cdr.u32();  // header.stamp.sec
    cdr.u32();  // header.stamp.nanosec
    cdr.skipString();
    const std::uint32_t count = cdr.u32();
    std::vector<Packet>& packets = scans.emplace_back();
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::int64_t sec = static_cast<std::int32_t>(cdr.u32());
      const std::int64_t nsec = cdr.u32();
      const std::uint8_t* data = cdr.bytes(1500);
      const std::uint32_t size = cdr.u32();
      if (size > 1500) throw std::runtime_error("PandarPacket size > 1500");
      Packet p;
      p.stamp_ns = sec * 1'000'000'000 + nsec;
      p.data.assign(data, data + size);
      packets.push_back(std::move(p));
    }
  }
  return scans;
}

std::vector<Eigen::Vector3f> readBinaryPcdXyz(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::string line;
  std::size_t points = 0;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "FIELDS" && line != "FIELDS x y z")
      throw std::runtime_error(file.string() + ": fields are not x y z");
    if (key == "POINTS") words >> points;
    if (key == "DATA") {
      if (line != "DATA binary") throw std::runtime_error(file.string() + ": not binary");
      break;
    }
  }
  std::vector<Eigen::Vector3f> xyz(points);
  in.read(reinterpret_cast<char*>(xyz.data()), static_cast<std::streamsize>(points * 12));
  if (!in) throw std::runtime_error(file.string() + ": truncated");
  return xyz;
}

}  // namespace socc::sensors::test_io
