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

bool FoxgloveSession::send(Dirty& dirty) {
  std::set<std::uint32_t> wanted;
  std::set<std::uint32_t> fresh;
  {
    const std::lock_guard<std::mutex> lock(subscriptions_mutex_);
    for (const auto& entry : subscriptions_) wanted.insert(entry.second);
    std::swap(fresh, fresh_);
  }
  voxels_dirty_ = voxels_dirty_ || dirty.reset || !dirty.blocks.empty();
  const auto now = std::chrono::steady_clock::now();
  const auto ns = static_cast<std::uint64_t>(nowMicros()) * 1000u;
  const auto due = [&](std::uint32_t c, bool changed) {
    return wanted.count(c) != 0 && (changed || fresh.count(c) != 0);
  };
  if (due(foxglove::kVoxels, voxels_dirty_ && now - last_voxels_ >= kVoxelInterval)) {
    const std::string cloud = model_.read(
        [&](const ViewModel& m) { return foxglove::voxels(m, ns, kMaxVoxelPoints); });
    if (!publish(foxglove::kVoxels, ns, cloud)) return false;
    voxels_dirty_ = false;
    last_voxels_ = now;
  } else if (voxels_dirty_) {
    wake();  // not yet due: come back
  }
  if (due(foxglove::kScans, dirty.robots)) {
    const std::string cloud = model_.read([&](const ViewModel& m) { return foxglove::scans(m, ns); });
    if (!publish(foxglove::kScans, ns, cloud)) return false;
  }
  if (due(foxglove::kRobots, dirty.robots)) {
    const std::string scene = model_.read([&](const ViewModel& m) { return foxglove::robots(m, ns); });
    if (!publish(foxglove::kRobots, ns, scene)) return false;
  }
  if (due(foxglove::kTransforms, dirty.robots)) {
    for (const std::string& tf :
         model_.read([&](const ViewModel& m) { return foxglove::transforms(m, ns); }))
      if (!publish(foxglove::kTransforms, ns, tf)) return false;
  }
  if (due(foxglove::kStats, dirty.stats)) {
    const std::string stats = model_.read([](const ViewModel& m) { return page::stats(m); });
    if (!stats.empty() && !publish(foxglove::kStats, ns, stats)) return false;
  }
  return true;
}

}  // namespace socc::view
