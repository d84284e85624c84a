#include "page_session.hpp"

#include <vector>

#include "page_protocol.hpp"

namespace socc::view {
namespace {
constexpr std::size_t kMessageBytes = 256 * 1024;  // block messages are split near this size
}  // namespace

bool PageSession::greet() {
  // The page starts over with a hello: everything it held is sent again.
  trajectory_sent_.clear();
  scan_sent_.clear();
  const std::string hello = model_.read([this](const ViewModel& m) {
    voxel_size_ = m.voxelSize();
    return page::hello(m);
  });
  return writeText(hello);
}

bool PageSession::send(Dirty& dirty) {
  if (dirty.reset) {  // the page drops everything; robots are sent whole again
    if (!writeText(page::reset())) return false;
    trajectory_sent_.clear();
    scan_sent_.clear();
    dirty.robots = true;
  }
  const bool new_geometry =
      model_.read([this](const ViewModel& m) { return m.voxelSize() != voxel_size_; });
  if (new_geometry) {
    if (!greet()) return false;
    dirty.robots = dirty.stats = true;
  }
  if (!dirty.blocks.empty() && !sendBlocks(dirty.blocks)) return false;
  if (dirty.robots && !sendRobots()) return false;
  if (dirty.stats) {
    const std::string stats = model_.read([](const ViewModel& m) { return page::stats(m); });
    if (!stats.empty() && !writeText(stats)) return false;
  }
  return true;
}

bool PageSession::sendBlocks(const std::set<BlockKey>& dirty) {
  const std::vector<BlockKey> keys(dirty.begin(), dirty.end());
  std::vector<std::uint8_t> message;
  for (std::size_t first = 0; first < keys.size() && !stopping();) {
    first += model_.read(
        [&](const ViewModel& m) { return page::blocks(m, keys, first, kMessageBytes, message); });
    if (!write(true, message.data(), message.size())) return false;
  }
  return true;
}

bool PageSession::sendRobots() {
  std::vector<std::vector<std::uint8_t>> scans;
  const auto now = std::chrono::steady_clock::now();
  const std::string robots = model_.read([&](const ViewModel& m) {
    for (const auto& [id, r] : m.robots()) {
      ScanSent& sent = scan_sent_[id];
      if (r.scan_seq == sent.seq || r.scan.empty() || now - sent.at < kScanInterval) continue;
      scans.push_back(page::scan(r));
      sent = {r.scan_seq, now};
    }
    return page::robots(m, trajectory_sent_);
  });
  if (!writeText(robots)) return false;
  for (const auto& s : scans)
    if (!write(true, s.data(), s.size())) return false;
  return true;
}

}  // namespace socc::view
