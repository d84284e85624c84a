// MCAP (mcap.dev/spec): magic, then records (opcode uint8, length uint64, content) of which
// Schema, Channel, Message and Chunk (records compressed with zstd or lz4, CRC-32 checked)
// matter here. Channels come from the summary section when the file has one, else from a
// first pass over the data; messages are yielded in file order. A damaged chunk is skipped
// and counted; a damaged record framing ends the reading (there is no way to resynchronise).
#include <unordered_map>

#include "bags/bag_reader.hpp"
#include "bags/chunked_bag_reader.hpp"
#include "bags/decompress.hpp"
#include "bags/record_file.hpp"

namespace socc::sensors::bags {

namespace {

constexpr std::uint8_t kMcapMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::uint64_t kRecordHeaderBytes = 9;  // opcode + length
constexpr std::uint64_t kFooterBytes = kRecordHeaderBytes + 20;

enum McapOpcode : std::uint8_t {
  kMcapFooter = 0x02,
  kMcapSchema = 0x03,
  kMcapChannel = 0x04,
  kMcapMessage = 0x05,
  kMcapChunk = 0x06,
  kMcapChunkIndex = 0x08,
  kMcapStatistics = 0x0B,
  kMcapDataEnd = 0x0F,
};

struct McapRecord {
  std::uint8_t opcode = 0;
  ByteView content;
};

/// The next record of a buffer of records (a chunk's or the summary's), or nullopt at its end.
std::optional<McapRecord> nextMcapRecord(ByteCursor& records) {
  if (records.done()) return std::nullopt;
  McapRecord r;
  r.opcode = records.read<std::uint8_t>();
  r.content = records.bytes64();
  return r;
}

class McapReader : public ChunkedBagReader {
 public:
  explicit McapReader(const std::filesystem::path& file) : file_(file) {
    try {
      const std::vector<std::uint8_t> magic = file_.read(0, sizeof(kMcapMagic));
      if (!std::equal(magic.begin(), magic.end(), kMcapMagic)) throw FormatError("no MCAP magic");
    } catch (const FormatError& e) {
      throw std::runtime_error(file.string() + ": not an MCAP file (" + e.what() + ")");
    }
    if (!readSummary()) scanChannels();
  }

  std::string containerProblems() const override {
    std::string p;
    if (unknown_channel_ > 0) {
      p += std::to_string(unknown_channel_) + " messages on channels never declared\n";
    }
    if (undecodable_ > 0) {
      p += std::to_string(undecodable_) + " malformed message records skipped\n";
    }
    return p;
  }

 private:
  /// Schemas and channels from the summary section; false when the file has none or it is
  /// damaged.
  bool readSummary() {
    if (file_.size() < sizeof(kMcapMagic) * 2 + kFooterBytes) return false;
    try {
      const std::uint64_t footer_at = file_.size() - sizeof(kMcapMagic) - kFooterBytes;
      const std::vector<std::uint8_t> footer = file_.read(footer_at, kFooterBytes);
      ByteCursor f{ByteView(footer)};
      if (f.read<std::uint8_t>() != kMcapFooter || f.read<std::uint64_t>() != 20) return false;
      const auto summary_start = f.read<std::uint64_t>();
      if (summary_start == 0 || summary_start > footer_at) return false;
      const std::vector<std::uint8_t> summary =
          file_.read(summary_start, footer_at - summary_start);
      ByteCursor records{ByteView(summary)};
      while (std::optional<McapRecord> r = nextMcapRecord(records)) {
        declare(*r);
        if (r->opcode == kMcapStatistics) readStatistics(r->content);
        if (r->opcode == kMcapChunkIndex) readChunkIndex(r->content);
      }
      return !channels_.empty();
    } catch (const FormatError&) {
      schemas_.clear();
      channels_.clear();
      channel_topic_.clear();
      chunk_channels_.clear();
      topics_.clear();
      return false;
    }
  }

  /// Without a summary: every Schema and Channel record of the data section, and the messages
  /// per channel. Damage is only noted when next() meets it.
  void scanChannels() {
    std::uint64_t pos = sizeof(kMcapMagic);
    try {
      while (pos + kRecordHeaderBytes <= file_.size()) {
        const std::vector<std::uint8_t> head = file_.read(pos, kRecordHeaderBytes);
        ByteCursor h{ByteView(head)};
        const auto opcode = h.read<std::uint8_t>();
        const auto length = h.read<std::uint64_t>();
        if (opcode == kMcapFooter || opcode == kMcapDataEnd) break;
        // A length past the end (it could even wrap the offset around): next() reports it.
        if (length > file_.size() - pos - kRecordHeaderBytes) break;
        if (opcode == kMcapSchema || opcode == kMcapChannel || opcode == kMcapMessage ||
            opcode == kMcapChunk) {
          const std::vector<std::uint8_t> content = file_.read(pos + kRecordHeaderBytes, length);
          if (opcode == kMcapChunk) {
            scanChunk(ByteView(content));
          } else {
            countOrDeclare({opcode, ByteView(content)});
          }
        }
        pos += kRecordHeaderBytes + length;
      }
    } catch (const FormatError&) {
      // next() reports it when it gets there.
    }
  }

  void scanChunk(ByteView content) {
    try {
      const std::vector<std::uint8_t> records = chunkRecords(content);
      ByteCursor c{ByteView(records)};
      while (std::optional<McapRecord> r = nextMcapRecord(c)) countOrDeclare(*r);
    } catch (const FormatError&) {
    }
  }

  void countOrDeclare(const McapRecord& r) {
    if (r.opcode == kMcapMessage) {
      ByteCursor c(r.content);
      const auto it = channel_topic_.find(c.read<std::uint16_t>());
      if (it != channel_topic_.end()) ++topics_[it->second].messages;
    } else {
      declare(r);
    }
  }

  /// Registers a Schema or Channel record (others are ignored).
  void declare(const McapRecord& r) {
    ByteCursor c(r.content);
    if (r.opcode == kMcapSchema) {
      const auto id = c.read<std::uint16_t>();
      std::string name = c.string32();
      schemas_[id] = {std::move(name), c.string32()};
    } else if (r.opcode == kMcapChannel) {
      const auto id = c.read<std::uint16_t>();
      if (channel_topic_.count(id) != 0) return;
      const auto schema_id = c.read<std::uint16_t>();
      TopicInfo t;
      t.name = c.string32();
      t.serialization = c.string32();
      const auto schema = schemas_.find(schema_id);
      t.type = schema != schemas_.end() ? schema->second.name : "";
      if (t.serialization == "cdr") t.encoding = Encoding::kCdr;
      if (t.serialization == "ros1") t.encoding = Encoding::kRos1;
      channels_[id] = t;
      channel_topic_[id] = topicIndex(t);
    }
  }

  /// The topic of a new channel: an existing one of that name and type, or a new one.
  std::size_t topicIndex(const TopicInfo& t) {
    for (std::size_t i = 0; i < topics_.size(); ++i) {
      if (topics_[i].name == t.name && topics_[i].type == t.type &&
          topics_[i].serialization == t.serialization) {
        return i;
      }
    }
    topics_.push_back(t);
    return topics_.size() - 1;
  }

  void readStatistics(ByteView content) {
    ByteCursor c(content);
    c.take(8 + 2 + 4 + 4 + 4 + 4 + 8 + 8);  // counts and times
    ByteCursor counts(c.bytes32());
    while (!counts.done()) {
      const auto channel = counts.read<std::uint16_t>();
      const auto n = counts.read<std::uint64_t>();
      const auto it = channel_topic_.find(channel);
      if (it != channel_topic_.end()) topics_[it->second].messages += n;
    }
  }

  /// A chunk index: the channels with messages in the chunk at chunk_start_offset.
  void readChunkIndex(ByteView content) {
    ByteCursor c(content);
    c.take(16);  // message start and end time
    std::vector<std::uint16_t>& channels = chunk_channels_[c.read<std::uint64_t>()];
    c.read<std::uint64_t>();  // chunk length
    ByteCursor offsets(c.bytes32());
    while (!offsets.done()) {
      channels.push_back(offsets.read<std::uint16_t>());
      offsets.read<std::uint64_t>();
    }
  }

  /// True when the summary says the chunk at offset holds no message of the selected topic,
  /// so it need not be decompressed (a camera topic's chunks, say).
  bool skippable(std::uint64_t offset) const {
    return otherTopicsOnly(offset, chunk_channels_, channel_topic_);
  }

  /// A Chunk record's content -> its records, decompressed and CRC-checked.
  static std::vector<std::uint8_t> chunkRecords(ByteView content) {
    ByteCursor c(content);
    c.take(16);  // message start and end time
    const auto uncompressed_size = c.read<std::uint64_t>();
    const auto crc = c.read<std::uint32_t>();
    const std::string compression = c.string32();
    std::vector<std::uint8_t> records = decompress(compression, c.bytes64(), uncompressed_size);
    if (crc != 0 && crc32Of(ByteView(records)) != crc) throw FormatError("chunk CRC mismatch");
    return records;
  }

  std::optional<BagMessage> nextTopLevel() override {
    try {
      if (pos_ + kRecordHeaderBytes > file_.size()) {
        throw FormatError("the file ends at byte " + std::to_string(file_.size()) +
                          " without a data end record");
      }
      const std::vector<std::uint8_t> head = file_.read(pos_, kRecordHeaderBytes);
      ByteCursor h{ByteView(head)};
      const auto opcode = h.read<std::uint8_t>();
      const auto length = h.read<std::uint64_t>();
      const std::uint64_t record_at = pos_;
      const std::uint64_t at = pos_ + kRecordHeaderBytes;
      if (opcode == kMcapFooter || opcode == kMcapDataEnd) {
        end();
        return std::nullopt;
      }
      if (length > file_.size() - at) {
        throw FormatError("record at byte " + std::to_string(pos_) + " runs past the end");
      }
      pos_ = at + length;
      if (opcode == kMcapChunk) {
        if (!skippable(record_at)) {
          const std::vector<std::uint8_t> content = file_.read(at, length);
          openChunk([&] { return chunkRecords(ByteView(content)); });
        }
      } else if (opcode == kMcapSchema || opcode == kMcapChannel || opcode == kMcapMessage) {
        const std::vector<std::uint8_t> content = file_.read(at, length);
        return handle({opcode, ByteView(content)});
      }
    } catch (const FormatError& e) {
      stop(e.what());
    }
    return std::nullopt;
  }

  std::optional<BagMessage> nextChunkRecord(ByteCursor& records) override {
    const std::optional<McapRecord> r = nextMcapRecord(records);
    return r ? handle(*r) : std::nullopt;
  }

  /// A Message of the selected topic, or nullopt (declarations are registered).
  std::optional<BagMessage> handle(const McapRecord& r) {
    if (r.opcode != kMcapMessage) {
      try {
        declare(r);
      } catch (const FormatError&) {
        ++undecodable_;
      }
      return std::nullopt;
    }
    ByteCursor c(r.content);
    if (c.remaining() < 2 + 4 + 8 + 8) {
      ++undecodable_;
      return std::nullopt;
    }
    const auto channel = c.read<std::uint16_t>();
    c.read<std::uint32_t>();  // sequence
    const auto log_time = c.read<std::uint64_t>();
    c.read<std::uint64_t>();  // publish time
    const auto it = channel_topic_.find(channel);
    if (it == channel_topic_.end()) {
      ++unknown_channel_;
      return std::nullopt;
    }
    if (selectedOther(it->second)) return std::nullopt;
    BagMessage m;
    m.topic = it->second;
    m.stamp_ns = static_cast<std::int64_t>(log_time);
    const ByteView data = c.take(c.remaining());
    m.data.assign(data.data, data.data + data.size);
    return m;
  }

  struct Schema {
    std::string name;
    std::string encoding;
  };

  RecordFile file_;
  std::unordered_map<std::uint16_t, Schema> schemas_;
  std::unordered_map<std::uint16_t, TopicInfo> channels_;
  std::unordered_map<std::uint16_t, std::size_t> channel_topic_;
  std::unordered_map<std::uint64_t, std::vector<std::uint16_t>> chunk_channels_;
  std::uint64_t pos_ = sizeof(kMcapMagic);
  std::uint64_t unknown_channel_ = 0;
  std::uint64_t undecodable_ = 0;
};

}  // namespace

std::unique_ptr<BagReader> openMcap(const std::filesystem::path& file) {
  return std::make_unique<McapReader>(file);
}

}  // namespace socc::sensors::bags
