#pragma once
// A Foxglove client (/foxglove, foxglove.websocket.v1): serverInfo and advertise on connect,
// then the latest state of each subscribed channel whenever it changed, each channel at most
// once per its interval (the whole voxel cloud every 2 s: Foxglove replaces a topic's point
// cloud with each message; scans 2 Hz; robots' scene with their trajectories 1 Hz).
#include <array>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "client_session.hpp"

namespace socc::view {

class FoxgloveSession : public ClientSession {
 public:
  static constexpr std::size_t kMaxVoxelPoints = 1000000;

  FoxgloveSession(ViewModel& model, FrameWriter writer, std::string session_id);
  void received(const std::string& text) override;

 private:
  bool greet() override;
  bool send(Dirty& dirty) override;
  /// Sends payload to every subscription of channel.
  bool publish(std::uint32_t channel, std::uint64_t time_ns, const std::string& payload);
  /// The payloads of channel now (one message, or one per robot for /tf).
  std::vector<std::string> payloads(std::uint32_t channel, std::uint64_t time_ns) const;

  std::string session_id_;
  std::mutex subscriptions_mutex_;
  std::map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id -> channel
  std::set<std::uint32_t> fresh_;  // channels subscribed since the last send: send them now
  // Per channel (index = channel id): changed since last sent, and when it was last sent.
  std::array<bool, 8> changed_{};
  std::array<std::chrono::steady_clock::time_point, 8> last_sent_{};
};

}  // namespace socc::view
