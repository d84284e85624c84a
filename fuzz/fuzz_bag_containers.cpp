// The bag container readers (ROS 2 .db3, MCAP, ROS 1 .bag) on arbitrary file content, and the
// messages they yield through the message parsers and the PointCloud2 conversion. The first
// byte picks the container; every reader must either return or throw std::runtime_error. ROS 1
// bags are read by rosbag_storage in a child process (bags/forked_reader.hpp): its crashes on
// damaged bags end that process only, and show here as an error or a problems() line.
#include <stdexcept>

#include "bags/bag_reader.hpp"
#include "bags/bag_topics.hpp"
#include "bags/pointcloud2_scan.hpp"
#include "temp_file.hpp"

namespace {

namespace bags = socc::sensors::bags;

// Bounds the work per input (a fuzzed file can hold many tiny messages).
constexpr int kMaxMessages = 256;

void decodeMessage(const bags::TopicInfo& topic, const bags::BagMessage& m) {
  if (!topic.encoding) return;
  const bags::MessageKind kind = bags::messageKind(topic.type);
  try {
    if (bags::isImuType(topic.type)) {
      bags::parseImu(bags::ByteView(m.data), *topic.encoding);
    } else if (bags::isTfMessageType(topic.type)) {
      bags::parseTfMessage(bags::ByteView(m.data), *topic.encoding);
    } else if (kind == bags::MessageKind::kPointCloud2) {
      bags::convertPointCloud2(bags::parsePointCloud2(bags::ByteView(m.data), *topic.encoding),
                               m.stamp_ns);
    } else if (kind != bags::MessageKind::kUnsupported) {
      std::vector<socc::sensors::Packet> packets;
      bags::appendPackets(kind, bags::ByteView(m.data), *topic.encoding, m.stamp_ns, packets);
    }
  } catch (const bags::FormatError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kSuffixes[] = {".db3", ".mcap", ".bag"};
  const char* suffix = kSuffixes[data[0] % 3];
  const socc::fuzz::TempFile file(data + 1, size - 1, suffix);
  try {
    const std::unique_ptr<bags::BagReader> reader = bags::openBagReader(file.path());
    try {
      bags::chooseTopic(*reader, "", file.path());
    } catch (const std::runtime_error&) {
    }
    for (int i = 0; i < kMaxMessages; ++i) {
      const std::optional<bags::BagMessage> m = reader->next();
      if (!m) break;
      decodeMessage(reader->topics().at(m->topic), *m);
    }
    reader->problems();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
