#include "bags/bag_topics.hpp"

#include <stdexcept>

namespace socc::sensors::bags {

namespace {

bool readableTopic(const TopicInfo& t) {
  return t.encoding && messageKind(t.type) != MessageKind::kUnsupported;
}

bool lidarCandidate(const TopicInfo& t) {
  return readableTopic(t) && !(messageKind(t.type) == MessageKind::kOusterPacket &&
                               t.name.find("imu") != std::string::npos);
}

}  // namespace

std::size_t chooseTopic(const BagReader& reader, const std::string& requested,
                        const std::filesystem::path& file) {
  const std::vector<TopicInfo>& topics = reader.topics();
  const std::string listing =
      "; its topics:\n" + describeTopics(topics) + "socc reads " + supportedMessageTypes();
  if (!requested.empty()) {
    for (std::size_t i = 0; i < topics.size(); ++i) {
      if (topics[i].name != requested) continue;
      if (!readableTopic(topics[i])) {
        throw std::runtime_error(file.string() + ": topic " + requested + " is " + topics[i].type +
                                 " in " + topics[i].serialization + ", which socc does not read" +
                                 listing);
      }
      return i;
    }
    throw std::runtime_error(file.string() + ": no topic " + requested + listing);
  }
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < topics.size(); ++i) {
    if (lidarCandidate(topics[i])) candidates.push_back(i);
  }
  if (candidates.size() == 1) return candidates[0];
  throw std::runtime_error(
      file.string() +
      (candidates.empty() ? ": no LiDAR topic" : ": several LiDAR topics, choose one (--topic)") +
      listing);
}

}  // namespace socc::sensors::bags
