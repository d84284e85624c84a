#pragma once
// A client of socc-view's own page (/ws): page_protocol.hpp's messages.
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
  std::map<std::string, std::int64_t> scan_sent_;  // per robot: seq of the last scan sent
};

}  // namespace socc::view
