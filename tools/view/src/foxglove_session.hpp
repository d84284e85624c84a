#pragma once
// A Foxglove client (/foxglove, foxglove.websocket.v1): serverInfo and advertise on connect,
// then the latest state of each subscribed channel whenever it changed (the whole voxel cloud
// at most every kVoxelInterval: Foxglove replaces a topic's point cloud with each message).
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "client_session.hpp"

namespace socc::view {

class FoxgloveSession : public ClientSession {
 public:
  static constexpr auto kVoxelInterval = std::chrono::seconds(2);
  static constexpr std::size_t kMaxVoxelPoints = 1000000;

  FoxgloveSession(ViewModel& model, FrameWriter writer, std::string session_id);
  void received(const std::string& text) override;

 private:
  bool greet() override;
  bool send(Dirty& dirty) override;
  /// Sends payload to every subscription of channel.
  bool publish(std::uint32_t channel, std::uint64_t time_ns, const std::string& payload);

  std::string session_id_;
  std::mutex subscriptions_mutex_;
  std::map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id -> channel
  std::set<std::uint32_t> fresh_;  // channels subscribed since the last send: send them now
  bool voxels_dirty_ = true;
  std::chrono::steady_clock::time_point last_voxels_{};
};

}  // namespace socc::view
