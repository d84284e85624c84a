#include "bag_seeds.hpp"

#include <sqlite3.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace socc::fuzz {

namespace {

/// Little-endian serialization; cdr: primitives aligned to their size after the 4-byte
/// encapsulation header, strings with their NUL.
class MessageBytes {
 public:
  explicit MessageBytes(bool cdr) : cdr_(cdr) {
    if (cdr_) out_ = std::string("\0\1\0\0", 4);
  }
  template <class T>
  MessageBytes& put(T v) {
    if (cdr_) {
      while ((out_.size() - 4) % sizeof(T) != 0) out_.push_back('\0');
    }
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
    return *this;
  }
  MessageBytes& str(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size() + (cdr_ ? 1 : 0)));
    out_ += s;
    if (cdr_) out_.push_back('\0');
    return *this;
  }
  MessageBytes& raw(const std::string& s) {
    out_ += s;
    return *this;
  }
  MessageBytes& header(std::uint32_t sec) {
    if (!cdr_) put(std::uint32_t{0});  // ROS 1 seq
    return put(sec).put(std::uint32_t{500}).str("lidar");
  }
  const std::string& bytes() const { return out_; }

 private:
  bool cdr_;
  std::string out_;
};

std::string twoPoints() {
  const float p[8] = {1.f, 2.f, 3.f, 0.f, 4.f, -5.f, 6.f, 0.05f};  // x y z t
  return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

std::string pointCloud2(bool cdr) {
  MessageBytes m(cdr);
  m.header(1700000000).put(std::uint32_t{1}).put(std::uint32_t{2}).put(std::uint32_t{4});
  const char* names[] = {"x", "y", "z", "t"};
  for (std::uint32_t i = 0; i < 4; ++i) {
    m.str(names[i]).put(4 * i).put(std::uint8_t{7}).put(std::uint32_t{1});
  }
  m.put(std::uint8_t{0}).put(std::uint32_t{16}).put(std::uint32_t{32});
  m.put(std::uint32_t{32}).raw(twoPoints()).put(std::uint8_t{1});
  return m.bytes();
}

std::string velodyneScan(bool cdr) {
  MessageBytes m(cdr);
  m.header(1700000000).put(std::uint32_t{1});
  m.put(std::uint32_t{1700000000}).put(std::uint32_t{1000}).raw(std::string(1206, '\xEE'));
  return m.bytes();
}

std::string pandarScan(bool cdr) {
  MessageBytes m(cdr);
  m.header(1700000000).put(std::uint32_t{1});
  m.put(std::uint32_t{1700000000}).put(std::uint32_t{1000}).raw(std::string(1500, '\xFF'));
  m.put(std::uint32_t{1080});
  return m.bytes();
}

std::string ousterPacket(bool cdr) {
  MessageBytes m(cdr);
  m.put(std::uint32_t{64}).raw(std::string(64, '\x01'));
  return m.bytes();
}

// --- MCAP (mcap.dev/spec) ---
std::string u16(std::uint16_t v) {
  return std::string(reinterpret_cast<const char*>(&v), 2);
}
std::string u32(std::uint32_t v) {
  return std::string(reinterpret_cast<const char*>(&v), 4);
}
std::string u64(std::uint64_t v) {
  return std::string(reinterpret_cast<const char*>(&v), 8);
}
std::string s32(const std::string& s) {
  return u32(static_cast<std::uint32_t>(s.size())) + s;
}

std::string mcapRecord(std::uint8_t op, const std::string& content) {
  return std::string(1, static_cast<char>(op)) + u64(content.size()) + content;
}

std::string mcapChannelRecords(const std::string& message) {
  return mcapRecord(0x03, u16(1) + s32("sensor_msgs/msg/PointCloud2") + s32("ros2msg") + s32("")) +
         mcapRecord(0x04, u16(1) + u16(1) + s32("/points") + s32("cdr") + u32(0)) +
         mcapRecord(0x05, u16(1) + u32(0) + u64(1700000000000000500) + u64(0) + message);
}

std::string mcapFile(bool chunked) {
  const std::string magic("\x89MCAP0\r\n", 8);
  std::string data = mcapChannelRecords(pointCloud2(true));
  if (chunked) {
    data = mcapRecord(
        0x06, u64(0) + u64(0) + u64(data.size()) + u32(0) + s32("") + u64(data.size()) + data);
  }
  return magic + mcapRecord(0x01, s32("ros2") + s32("socc seeds")) + data +
         mcapRecord(0x0F, u32(0)) + mcapRecord(0x02, u64(0) + u64(0) + u32(0)) + magic;
}

// --- ROS 1 bag 2.0 (wiki.ros.org/Bags/Format/2.0) ---
std::string ros1Field(const std::string& name, const std::string& value) {
  return s32(name + "=" + value);
}

std::string ros1Record(const std::string& fields, const std::string& data) {
  return s32(fields) + s32(data);
}

/// An indexed bag (rosbag_storage reads no other): bag header, one uncompressed chunk with a
/// connection and a message, the chunk's index data, then the index section (connection, chunk
/// info) that index_pos points to.
std::string ros1Bag() {
  const std::string magic = "#ROSBAG V2.0\n";
  const std::string time = u32(1700000000) + u32(500);
  const std::string conn =
      ros1Field("op", "\x07") + ros1Field("conn", u32(0)) + ros1Field("topic", "/points");
  const std::string info = ros1Field("topic", "/points") +
                           ros1Field("type", "sensor_msgs/PointCloud2") +
                           ros1Field("md5sum", "1158d486dd51d683ce2f1be655c3c181");
  const std::string connection = ros1Record(conn, info);
  const std::string message =
      ros1Field("op", std::string("\x02", 1)) + ros1Field("conn", u32(0)) + ros1Field("time", time);
  const std::string records = connection + ros1Record(message, pointCloud2(false));
  const std::string chunk =
      ros1Record(ros1Field("op", "\x05") + ros1Field("compression", "none") +
                     ros1Field("size", u32(static_cast<std::uint32_t>(records.size()))),
                 records);
  // The message's offset inside the chunk's records: after the connection record.
  const std::string index_data =
      ros1Record(ros1Field("op", "\x04") + ros1Field("ver", u32(1)) + ros1Field("conn", u32(0)) +
                     ros1Field("count", u32(1)),
                 time + u32(static_cast<std::uint32_t>(connection.size())));
  const auto header = [](std::uint64_t index_pos) {
    return ros1Record(ros1Field("op", "\x03") + ros1Field("index_pos", u64(index_pos)) +
                          ros1Field("conn_count", u32(1)) + ros1Field("chunk_count", u32(1)),
                      std::string(16, ' '));
  };
  const std::uint64_t chunk_pos = magic.size() + header(0).size();
  const std::uint64_t index_pos = chunk_pos + chunk.size() + index_data.size();
  const std::string chunk_info = ros1Record(
      ros1Field("op", "\x06") + ros1Field("ver", u32(1)) + ros1Field("chunk_pos", u64(chunk_pos)) +
          ros1Field("start_time", time) + ros1Field("end_time", time) + ros1Field("count", u32(1)),
      u32(0) + u32(1));
  return magic + header(index_pos) + chunk + index_data + connection + chunk_info;
}

// --- ROS 2 .db3 (SQLite) ---
void exec(sqlite3* db, const char* sql) {
  if (sqlite3_exec(db, sql, nullptr, nullptr, nullptr) != SQLITE_OK) {
    throw std::runtime_error(std::string("sqlite: ") + sqlite3_errmsg(db));
  }
}

std::string db3File(const std::filesystem::path& scratch) {
  const std::filesystem::path file = scratch / "seed.db3";
  std::filesystem::remove(file);
  sqlite3* db = nullptr;
  if (sqlite3_open(file.c_str(), &db) != SQLITE_OK) throw std::runtime_error("sqlite open");
  exec(db,
       "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
       " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
       "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
       " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
       "INSERT INTO topics VALUES (1, '/points', 'sensor_msgs/msg/PointCloud2', 'cdr', '');");
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages VALUES (1, 1, 1700000000000000500, ?)", -1, &s,
                     nullptr);
  const std::string message = pointCloud2(true);
  sqlite3_bind_blob(s, 1, message.data(), static_cast<int>(message.size()), SQLITE_TRANSIENT);
  sqlite3_step(s);
  sqlite3_finalize(s);
  sqlite3_close(db);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(file);
  return bytes;
}

std::string selected(int selector, const std::string& content) {
  return std::string(1, static_cast<char>(selector)) + content;
}

}  // namespace

std::vector<BagSeed> bagSeeds(const std::filesystem::path& scratch) {
  const std::string c = "fuzz_bag_containers";
  const std::string m = "fuzz_bag_messages";
  std::vector<BagSeed> seeds = {
      {c, "db3", selected(0, db3File(scratch))},
      {c, "mcap", selected(1, mcapFile(false))},
      {c, "mcap_chunked", selected(1, mcapFile(true))},
      {c, "ros1_bag", selected(2, ros1Bag())},
  };
  for (const bool cdr : {true, false}) {
    const int e = cdr ? 0 : 1;
    const std::string tag = cdr ? "_cdr" : "_ros1";
    seeds.push_back({m, "pointcloud2" + tag, selected(e, pointCloud2(cdr))});
    seeds.push_back({m, "velodyne_scan" + tag, selected(e | 2, velodyneScan(cdr))});
    seeds.push_back({m, "pandar_scan" + tag, selected(e | 4, pandarScan(cdr))});
    seeds.push_back({m, "ouster_packet" + tag, selected(e | 6, ousterPacket(cdr))});
  }
  return seeds;
}

}  // namespace socc::fuzz
