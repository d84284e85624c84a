// ROS 1 bags, format 2.0 (wiki.ros.org/Bags/Format/2.0): "#ROSBAG V2.0\n", then records of
// (uint32 header length, header fields "name=value" each uint32 length-prefixed, uint32 data
// length, data). op 0x03 bag header (index_pos), 0x05 chunk (compression none / bz2 / lz4,
// uncompressed size) holding 0x07 connection and 0x02 message data records, then the index
// section after index_pos: connections again and 0x06 chunk infos (message counts).
// Debian's librosbag-storage was not used: it crashes (SIGSEGV) on corrupted bags and its
// CMake / pkg-config files need an ament environment (docs/sensors_bags.md).
#include <cstring>
#include <map>
#include <unordered_map>

#include "bags/bag_reader.hpp"
#include "bags/chunked_bag_reader.hpp"
#include "bags/decompress.hpp"
#include "bags/record_file.hpp"

namespace socc::sensors::bags {

namespace {

constexpr char kRos1Magic[] = "#ROSBAG V2.0\n";
constexpr std::uint64_t kRos1MagicBytes = sizeof(kRos1Magic) - 1;

enum Ros1Op : std::uint8_t {
  kRos1MessageData = 0x02,
  kRos1BagHeader = 0x03,
  kRos1Chunk = 0x05,
  kRos1ChunkInfo = 0x06,
  kRos1Connection = 0x07,
};

/// A record's header fields by name (values are raw bytes).
using Ros1Fields = std::map<std::string, ByteView>;

Ros1Fields parseRos1Fields(ByteView header) {
  Ros1Fields fields;
  ByteCursor c(header);
  while (!c.done()) {
    const ByteView field = c.bytes32();
    const auto* eq = static_cast<const std::uint8_t*>(std::memchr(field.data, '=', field.size));
    if (eq == nullptr) throw FormatError("header field without '='");
    const auto name_len = static_cast<std::size_t>(eq - field.data);
    fields[field.sub(0, name_len).str()] = field.sub(name_len + 1, field.size - name_len - 1);
  }
  return fields;
}

template <class T>
T ros1Field(const Ros1Fields& fields, const char* name) {
  const auto it = fields.find(name);
  if (it == fields.end()) throw FormatError(std::string("record without field ") + name);
  if (it->second.size != sizeof(T)) throw FormatError(std::string("field ") + name + " size");
  return loadValue<T>(it->second.data, false);
}

std::string ros1StringField(const Ros1Fields& fields, const char* name) {
  const auto it = fields.find(name);
  return it == fields.end() ? std::string() : it->second.str();
}

struct Ros1Record {
  std::uint8_t op = 0;
  Ros1Fields fields;
  ByteView data;
};

/// The next record of a buffer of records (a chunk's), or nullopt at its end.
std::optional<Ros1Record> nextRos1Record(ByteCursor& records) {
  if (records.done()) return std::nullopt;
  Ros1Record r;
  r.fields = parseRos1Fields(records.bytes32());
  r.op = ros1Field<std::uint8_t>(r.fields, "op");
  r.data = records.bytes32();
  return r;
}

class Ros1BagReader : public ChunkedBagReader {
 public:
  explicit Ros1BagReader(const std::filesystem::path& file) : file_(file) {
    try {
      const std::vector<std::uint8_t> magic = file_.read(0, kRos1MagicBytes);
      if (std::memcmp(magic.data(), kRos1Magic, kRos1MagicBytes) != 0) {
        throw FormatError("no '#ROSBAG V2.0' line");
      }
      const OwnedRecord header = readTopLevel(kRos1MagicBytes);
      if (header.record.op != kRos1BagHeader) throw FormatError("no bag header record");
      index_pos_ = ros1Field<std::uint64_t>(header.record.fields, "index_pos");
    } catch (const FormatError& e) {
      throw std::runtime_error(file.string() + ": not a ROS 1 bag (" + e.what() + ")");
    }
    pos_ = kRos1MagicBytes;
    if (!readIndex()) scanConnections();
  }

  std::string containerProblems() const override {
    if (unknown_connection_ == 0) return {};
    return std::to_string(unknown_connection_) + " messages on connections never declared\n";
  }

 private:
  /// A top-level record with the bytes its fields and data point into.
  struct OwnedRecord {
    std::vector<std::uint8_t> header;
    std::vector<std::uint8_t> data;
    Ros1Record record;
    std::uint64_t next = 0;  // the offset after it
  };

  OwnedRecord readTopLevel(std::uint64_t offset) {
    OwnedRecord o;
    const auto header_len = loadValue<std::uint32_t>(file_.read(offset, 4).data(), false);
    o.header = file_.read(offset + 4, header_len);
    const std::uint64_t data_at = offset + 8 + header_len;
    const auto data_len = loadValue<std::uint32_t>(file_.read(data_at - 4, 4).data(), false);
    o.data = file_.read(data_at, data_len);
    o.record.fields = parseRos1Fields(ByteView(o.header));
    o.record.op = ros1Field<std::uint8_t>(o.record.fields, "op");
    o.record.data = ByteView(o.data);
    o.next = data_at + data_len;
    return o;
  }

  /// Connections and message counts from the index section; false when there is none.
  bool readIndex() {
    if (index_pos_ == 0 || index_pos_ >= file_.size()) return false;
    try {
      std::uint64_t pos = index_pos_;
      while (pos < file_.size()) {
        const OwnedRecord o = readTopLevel(pos);
        if (o.record.op == kRos1Connection) declare(o.record);
        if (o.record.op == kRos1ChunkInfo) countChunkInfo(o.record);
        pos = o.next;
      }
      return !topics_.empty();
    } catch (const FormatError&) {
      connection_topic_.clear();
      chunk_connections_.clear();
      topics_.clear();
      return false;
    }
  }

  /// Without an index: every connection record in the chunks (damage is noted by next()).
  void scanConnections() {
    std::uint64_t pos = kRos1MagicBytes;
    try {
      while (pos < file_.size() && (index_pos_ == 0 || pos < index_pos_)) {
        const OwnedRecord o = readTopLevel(pos);
        pos = o.next;
        if (o.record.op == kRos1Connection) declare(o.record);
        if (o.record.op != kRos1Chunk) continue;
        try {
          const std::vector<std::uint8_t> records = chunkRecords(o.record);
          ByteCursor c{ByteView(records)};
          while (std::optional<Ros1Record> inner = nextRos1Record(c)) {
            if (inner->op == kRos1Connection) declare(*inner);
            if (inner->op == kRos1MessageData) count(*inner);
          }
        } catch (const FormatError&) {
        }
      }
    } catch (const FormatError&) {
    }
  }

  void count(const Ros1Record& r) {
    const auto it = connection_topic_.find(ros1Field<std::uint32_t>(r.fields, "conn"));
    if (it != connection_topic_.end()) ++topics_[it->second].messages;
  }

  /// A chunk info record: messages per connection in the chunk at chunk_pos.
  void countChunkInfo(const Ros1Record& r) {
    std::vector<std::uint32_t>& connections =
        chunk_connections_[ros1Field<std::uint64_t>(r.fields, "chunk_pos")];
    ByteCursor c(r.data);
    while (!c.done()) {
      const auto conn = c.read<std::uint32_t>();
      const auto n = c.read<std::uint32_t>();
      connections.push_back(conn);
      const auto it = connection_topic_.find(conn);
      if (it != connection_topic_.end()) topics_[it->second].messages += n;
    }
  }

  /// True when the index says the chunk at offset holds no message of the selected topic, so
  /// it need not be decompressed (a camera topic's chunks, say).
  bool skippable(std::uint64_t offset) const {
    return otherTopicsOnly(offset, chunk_connections_, connection_topic_);
  }

  /// A connection record: its topic and, in its data, the type (fields topic, type, md5sum...).
  void declare(const Ros1Record& r) {
    const auto conn = ros1Field<std::uint32_t>(r.fields, "conn");
    if (connection_topic_.count(conn) != 0) return;
    const Ros1Fields info = parseRos1Fields(r.data);
    TopicInfo t;
    t.name = ros1StringField(r.fields, "topic");
    t.type = ros1StringField(info, "type");
    t.serialization = "ros1";
    t.encoding = Encoding::kRos1;
    for (std::size_t i = 0; i < topics_.size(); ++i) {
      if (topics_[i].name == t.name && topics_[i].type == t.type) {
        connection_topic_[conn] = i;
        return;
      }
    }
    connection_topic_[conn] = topics_.size();
    topics_.push_back(std::move(t));
  }

  static std::vector<std::uint8_t> chunkRecords(const Ros1Record& chunk) {
    return decompress(ros1StringField(chunk.fields, "compression"), chunk.data,
                      ros1Field<std::uint32_t>(chunk.fields, "size"));
  }

  std::optional<BagMessage> nextTopLevel() override {
    try {
      if (pos_ >= file_.size() || (index_pos_ != 0 && pos_ >= index_pos_)) {
        if (index_pos_ > file_.size()) throw FormatError("the file ends before its index");
        end();
        return std::nullopt;
      }
      const std::uint64_t at = pos_;
      const OwnedRecord o = readTopLevel(pos_);
      pos_ = o.next;
      if (o.record.op == kRos1Chunk) {
        if (!skippable(at)) openChunk([&] { return chunkRecords(o.record); });
      } else {
        return handle(o.record);
      }
    } catch (const FormatError& e) {
      stop(std::string(e.what()) + " (at byte " + std::to_string(pos_) + ")");
    }
    return std::nullopt;
  }

  std::optional<BagMessage> nextChunkRecord(ByteCursor& records) override {
    const std::optional<Ros1Record> r = nextRos1Record(records);
    return r ? handle(*r) : std::nullopt;
  }

  /// A message of the selected topic, or nullopt (connections are registered).
  std::optional<BagMessage> handle(const Ros1Record& r) {
    if (r.op == kRos1Connection) declare(r);
    if (r.op != kRos1MessageData) return std::nullopt;
    const auto it = connection_topic_.find(ros1Field<std::uint32_t>(r.fields, "conn"));
    if (it == connection_topic_.end()) {
      ++unknown_connection_;
      return std::nullopt;
    }
    if (selectedOther(it->second)) return std::nullopt;
    const auto time = ros1Field<std::uint64_t>(r.fields, "time");
    const auto nsec = static_cast<std::uint32_t>(time >> 32);
    if (nsec >= 1'000'000'000u)
      throw FormatError("message time with " + std::to_string(nsec) + " ns");
    BagMessage m;
    m.topic = it->second;
    m.stamp_ns = static_cast<std::int64_t>(time & 0xFFFFFFFFu) * 1'000'000'000 + nsec;
    m.data.assign(r.data.data, r.data.data + r.data.size);
    return m;
  }

  RecordFile file_;
  std::uint64_t index_pos_ = 0;
  std::unordered_map<std::uint32_t, std::size_t> connection_topic_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> chunk_connections_;
  std::uint64_t pos_ = 0;
  std::uint64_t unknown_connection_ = 0;
};

}  // namespace

std::unique_ptr<BagReader> openRos1Bag(const std::filesystem::path& file) {
  return std::make_unique<Ros1BagReader>(file);
}

}  // namespace socc::sensors::bags
