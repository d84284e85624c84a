#pragma once
// A client of socc-view's own page (/ws): page_protocol.hpp's messages.
#include <chrono>
#include <map>
#include <string>

#include "client_session.hpp"

namespace socc::view {

class PageSession : public ClientSession {
 public:
  using ClientSession::ClientSession;

 private:
  bool greet() override;
  bool send(Dirty& dirty) override;
  bool sendBlocks(const std::set<BlockKey>& keys);
  bool sendRobots();

  double voxel_size_ = 0.0;  // of the last hello
  std::map<std::string, std::size_t> trajectory_sent_;
  /// A robot's latest scan goes out at most this often (the page shows the scan's shape).
  static constexpr auto kScanInterval = std::chrono::milliseconds(500);
  struct ScanSent {
    std::int64_t seq = -1;
    std::chrono::steady_clock::time_point at{};
  };
  std::map<std::string, ScanSent> scan_sent_;  // per robot: the last scan sent
};

}  // namespace socc::view
