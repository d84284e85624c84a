#include "foxglove_session.hpp"

#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "foxglove_protocol.hpp"
#include "page_protocol.hpp"
#include "socc/wall_clock.hpp"

namespace socc::view {

FoxgloveSession::FoxgloveSession(ViewModel& model, FrameWriter writer, std::string session_id)
    : ClientSession(model, std::move(writer)), session_id_(std::move(session_id)) {}

bool FoxgloveSession::greet() {
  return writeText(foxglove::serverInfo(session_id_)) && writeText(foxglove::advertise());
}

void FoxgloveSession::received(const std::string& text) {
  const nlohmann::json message = nlohmann::json::parse(text, nullptr, false);
  if (!message.is_object() || !message.contains("op")) return;  // not ours: ignored
  const std::string op = message.value("op", "");
  {
    const std::lock_guard<std::mutex> lock(subscriptions_mutex_);
    if (op == "subscribe" && message.contains("subscriptions") &&
        message["subscriptions"].is_array()) {
      for (const auto& s : message["subscriptions"]) {
        if (!s.is_object() || !s.contains("id") || !s.contains("channelId")) continue;
        if (!s["id"].is_number_unsigned() || !s["channelId"].is_number_unsigned()) continue;
        const auto channel = s["channelId"].get<std::uint32_t>();
        if (channel < 1 || channel > foxglove::kNumChannels) continue;
        subscriptions_[s["id"].get<std::uint32_t>()] = channel;
        fresh_.insert(channel);
      }
    } else if (op == "unsubscribe" && message.contains("subscriptionIds") &&
               message["subscriptionIds"].is_array()) {
      for (const auto& id : message["subscriptionIds"])
        if (id.is_number_unsigned()) subscriptions_.erase(id.get<std::uint32_t>());
    } else {
      return;
    }
  }
  wake();
}

bool FoxgloveSession::publish(std::uint32_t channel, std::uint64_t time_ns,
                              const std::string& payload) {
  std::vector<std::uint32_t> ids;
  {
    const std::lock_guard<std::mutex> lock(subscriptions_mutex_);
    for (const auto& [id, c] : subscriptions_)
      if (c == channel) ids.push_back(id);
  }
  for (const std::uint32_t id : ids) {
    const std::vector<std::uint8_t> frame = foxglove::messageData(id, time_ns, payload);
    if (!write(true, frame.data(), frame.size())) return false;
  }
  return true;
}

namespace {
// Shortest time between two messages of a channel (index = channel id).
std::chrono::milliseconds minInterval(std::uint32_t channel) {
  switch (channel) {
    case foxglove::kVoxels:
      return std::chrono::milliseconds(2000);
    case foxglove::kScans:
      return std::chrono::milliseconds(500);
    case foxglove::kRobots:
      return std::chrono::milliseconds(1000);
    default:
      return std::chrono::milliseconds(0);
  }
}
}  // namespace

std::vector<std::string> FoxgloveSession::payloads(std::uint32_t channel, std::uint64_t ns) const {
  return model_.read([&](const ViewModel& m) -> std::vector<std::string> {
    switch (channel) {
      case foxglove::kVoxels:
        return {foxglove::voxels(m, ns, kMaxVoxelPoints)};
      case foxglove::kScans:
        return {foxglove::scans(m, ns)};
      case foxglove::kRobots:
        return {foxglove::robots(m, ns)};
      case foxglove::kTransforms:
        return foxglove::transforms(m, ns);
      default: {
        std::string stats = page::stats(m);
        if (stats.empty()) return {};
        return {std::move(stats)};
      }
    }
  });
}

bool FoxgloveSession::send(Dirty& dirty) {
  std::set<std::uint32_t> wanted;
  std::set<std::uint32_t> fresh;
  {
    const std::lock_guard<std::mutex> lock(subscriptions_mutex_);
    for (const auto& entry : subscriptions_) wanted.insert(entry.second);
    std::swap(fresh, fresh_);
  }
  changed_[foxglove::kVoxels] = changed_[foxglove::kVoxels] || dirty.reset || !dirty.blocks.empty();
  for (const std::uint32_t c : {foxglove::kScans, foxglove::kRobots, foxglove::kTransforms})
    changed_[c] = changed_[c] || dirty.robots || dirty.reset;
  changed_[foxglove::kStats] = changed_[foxglove::kStats] || dirty.stats;
  const auto now = std::chrono::steady_clock::now();
  const auto ns = static_cast<std::uint64_t>(nowMicros()) * 1000u;
  bool later = false;
  for (std::uint32_t c = 1; c <= foxglove::kNumChannels; ++c) {
    if (wanted.count(c) == 0 || !(changed_[c] || fresh.count(c) != 0)) continue;
    if (fresh.count(c) == 0 && now - last_sent_[c] < minInterval(c)) {
      later = true;  // throttled: the newest state goes out when the interval has passed
      continue;
    }
    for (const std::string& payload : payloads(c, ns))
      if (!publish(c, ns, payload)) return false;
    changed_[c] = false;
    last_sent_[c] = now;
  }
  if (later) wake();
  return true;
}

}  // namespace socc::view
