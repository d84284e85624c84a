// ROS 1 bags (format 2.0: chunks none, bz2, lz4) through Debian's rosbag_storage (rosbag::Bag,
// rosbag::View): the connections give the topics, each message's serialized bytes go to socc's
// parsers. rosbag_storage trusts the lengths and offsets stored in the file (a damaged bag can
// make it read past its buffers: docs/sensors_bags.md), so it runs in a forked child process
// (ForkedReader): a helper program, socc-ros1-bag-reader, started by posix_spawn (a process
// forked without exec would inherit the locks other threads hold, e.g. ASan's allocator's:
// docs/sensors_bags.md); what it throws, or a crash, becomes an error or a problems() line here.
#include <console_bridge/console.h>
#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "bags/bag_reader.hpp"
#include "bags/forked_reader.hpp"
#include "bags/ros1_bag_child.hpp"

namespace socc::sensors::bags {

namespace {

// Frames from the child process.
constexpr std::uint8_t kTopicFrame = ForkedReader::kFirstUserFrame;  // u64 count, name, type
constexpr std::uint8_t kMessageFrame = kTopicFrame + 1;    // data, then u32 topic, i64 stamp [ns]
constexpr std::uint8_t kDamageFrame = kTopicFrame + 2;     // why a message could not be read
constexpr std::uint8_t kTopicsEndFrame = kTopicFrame + 3;  // then the child waits for a topic
constexpr std::size_t kMessageTrailerBytes = 12;

template <class T>
ByteView valueView(const T& value) {
  return {reinterpret_cast<const std::uint8_t*>(&value), sizeof(T)};
}

// ---- In the child process: rosbag_storage ----

/// Topics as (name, type) pairs in connection order (a topic recorded by several publishers
/// has several connections) and the number of messages of each.
struct Ros1Topics {
  std::vector<TopicInfo> topics;
  std::size_t indexOf(const std::string& name, const std::string& type) const {
    for (std::size_t i = 0; i < topics.size(); ++i) {
      if (topics[i].name == name && topics[i].type == type) return i;
    }
    return topics.size();
  }
};

Ros1Topics ros1Topics(rosbag::Bag& bag) {
  Ros1Topics t;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (t.indexOf(c->topic, c->datatype) < t.topics.size()) continue;
    TopicInfo info;
    info.name = c->topic;
    info.type = c->datatype;
    info.serialization = "ros1";
    info.encoding = Encoding::kRos1;
    t.topics.push_back(std::move(info));
  }
  for (TopicInfo& info : t.topics)
    info.messages = rosbag::View(bag, rosbag::TopicQuery(info.name)).size();
  return t;
}

void openBag(rosbag::Bag& bag, const std::string& file) {
  // rosbag_storage logs through console_bridge; its errors reach the parent as exceptions.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  try {
    bag.open(file, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw std::runtime_error(
        "the bag has no index (a recording that was not closed: `rosbag reindex` rebuilds it)");
  } catch (const rosbag::BagIOException& e) {
    // Opening reads the header and the index at the end of the file: a cut file fails here.
    throw std::runtime_error(std::string("its index cannot be read (a truncated file? `rosbag "
                                         "reindex` rebuilds the index of a cut bag): ") +
                             e.what());
  }
}

}  // namespace

void readRos1BagInChild(const std::string& file, FrameWriter& out) {
  rosbag::Bag bag;
  openBag(bag, file);
  const Ros1Topics t = ros1Topics(bag);
  for (const TopicInfo& info : t.topics) {
    // Strings as uint32 length + bytes (ByteCursor::string32).
    const std::uint64_t count = info.messages;
    const auto name_bytes = static_cast<std::uint32_t>(info.name.size());
    const auto type_bytes = static_cast<std::uint32_t>(info.type.size());
    out.write(kTopicFrame, {valueView(count), valueView(name_bytes), textBytes(info.name),
                            valueView(type_bytes), textBytes(info.type)});
  }
  out.write(kTopicsEndFrame, {});
  const std::optional<std::uint64_t> selected = out.receive();
  if (!selected) return;  // the reader was closed before reading
  const bool all = *selected >= t.topics.size();
  rosbag::View view =
      all ? rosbag::View(bag) : rosbag::View(bag, rosbag::TopicQuery(t.topics[*selected].name));
  std::vector<std::uint8_t> data;
  for (const rosbag::MessageInstance& m : view) {
    const auto topic = static_cast<std::uint32_t>(t.indexOf(m.getTopic(), m.getDataType()));
    if (!all && topic != *selected) continue;
    const ros::Time time = m.getTime();
    try {
      data.resize(m.size());  // decompresses the chunk: damage throws here or in write()
      ros::serialization::OStream stream(data.data(), static_cast<std::uint32_t>(data.size()));
      m.write(stream);
    } catch (const std::exception& e) {
      char at[32];
      std::snprintf(at, sizeof(at), "%u.%09u", time.sec, time.nsec);
      const std::string why =
          "the " + m.getTopic() + " message recorded at " + at + " s: " + e.what();
      out.write(kDamageFrame, {textBytes(why)});
      continue;
    }
    const std::int64_t stamp_ns = static_cast<std::int64_t>(time.sec) * 1'000'000'000 + time.nsec;
    out.write(kMessageFrame, {ByteView(data), valueView(topic), valueView(stamp_ns)});
  }
}

// ---- In this process ----

namespace {

/// The helper program: $SOCC_ROS1_BAG_READER, the one installed beside the running program
/// (bin/../libexec/socc/), or the build tree's, whichever exists first.
std::string helperProgram() {
  namespace fs = std::filesystem;
  std::vector<fs::path> tried;
  if (const char* env = std::getenv("SOCC_ROS1_BAG_READER"); env != nullptr && *env != '\0')
    tried.emplace_back(env);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    tried.push_back(self.parent_path().parent_path() / SOCC_LIBEXEC_DIR / "socc" /
                    "socc-ros1-bag-reader");
  tried.emplace_back(SOCC_ROS1_BAG_READER_BUILD);
  std::string looked;
  for (const fs::path& p : tried) {
    if (::access(p.c_str(), X_OK) == 0) return p.string();
    looked += (looked.empty() ? "" : ", ") + p.string();
  }
  throw std::runtime_error(
      "the ROS 1 bag reader helper socc-ros1-bag-reader is missing (looked "
      "for " +
      looked + "; set SOCC_ROS1_BAG_READER)");
}

TopicInfo decodeTopic(const Frame& f) {
  ByteCursor c{ByteView(f.payload)};
  TopicInfo t;
  t.messages = c.read<std::uint64_t>();
  t.name = c.string32();
  t.type = c.string32();
  t.serialization = "ros1";
  t.encoding = Encoding::kRos1;
  return t;
}

class Ros1BagReader : public BagReader {
 public:
  explicit Ros1BagReader(const std::filesystem::path& file) : file_(file.string()) {
    requireBagMagic();
    reader_.emplace(helperProgram(), std::vector<std::string>{file_});
    try {
      while (true) {
        const std::optional<Frame> f = reader_->next();
        if (!f) throw std::runtime_error("the reader process ended before the topic list");
        if (f->kind == ForkedReader::kFailed) throw std::runtime_error(f->text());
        if (f->kind == kTopicsEndFrame) break;
        if (f->kind == kTopicFrame) topics_.push_back(decodeTopic(*f));
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(file_ + ": not a readable ROS 1 bag (" + e.what() + ")");
    }
  }

  const std::vector<TopicInfo>& topics() const override { return topics_; }

  void select(std::size_t topic) override { selected_ = topic; }

  std::optional<BagMessage> next() override {
    if (!started_) {
      reader_->send(selected_.value_or(topics_.size()));
      started_ = true;
    }
    while (std::optional<Frame> f = reader_->next()) {
      if (f->kind == kDamageFrame) {
        if (damaged_++ == 0) first_damage_ = f->text();
      } else if (f->kind == ForkedReader::kFailed) {
        stop_reason_ = f->text();
      } else if (f->kind == kMessageFrame && f->payload.size() >= kMessageTrailerBytes) {
        if (std::optional<BagMessage> m = decodeMessage(std::move(f->payload))) return m;
      }
    }
    return std::nullopt;
  }

  std::string problems() const override {
    std::string p;
    if (damaged_ > 0) {
      p += std::to_string(damaged_) +
           " messages unreadable (damaged chunks; first: " + first_damage_ + ")\n";
    }
    if (!stop_reason_.empty()) p += "reading stopped: " + stop_reason_ + "\n";
    return p;
  }

 private:
  /// A file that is no bag at all is told so here, before rosbag_storage reads it.
  void requireBagMagic() const {
    static constexpr char kMagic[] = "#ROSBAG V";  // then "2.0\n" (or 1.2, also read)
    char head[sizeof(kMagic) - 1] = {};
    std::ifstream in(file_, std::ios::binary);
    if (!in) throw std::runtime_error(file_ + ": cannot open");
    in.read(head, sizeof(head));
    if (!in || std::memcmp(head, kMagic, sizeof(head)) != 0)
      throw std::runtime_error(file_ + ": not a ROS 1 bag (no '#ROSBAG V' line)");
  }

  /// The payload is the message's bytes with topic and stamp behind them (no copy to split).
  std::optional<BagMessage> decodeMessage(std::vector<std::uint8_t> payload) {
    const std::size_t n = payload.size() - kMessageTrailerBytes;
    BagMessage m;
    std::uint32_t topic = 0;
    std::memcpy(&topic, payload.data() + n, sizeof(topic));
    std::memcpy(&m.stamp_ns, payload.data() + n + sizeof(topic), sizeof(m.stamp_ns));
    if (topic >= topics_.size() || (selected_ && topic != *selected_)) return std::nullopt;
    m.topic = topic;
    payload.resize(n);
    m.data = std::move(payload);
    return m;
  }

  std::string file_;
  std::vector<TopicInfo> topics_;
  std::optional<std::size_t> selected_;
  std::optional<ForkedReader> reader_;  // one child: the topic list, then the messages
  bool started_ = false;                // the topic to read was sent
  std::uint64_t damaged_ = 0;
  std::string first_damage_;
  std::string stop_reason_;
};

}  // namespace

std::unique_ptr<BagReader> openRos1Bag(const std::filesystem::path& file) {
  return std::make_unique<Ros1BagReader>(file);
}

}  // namespace socc::sensors::bags
