#include "client_session.hpp"

#include <chrono>
#include <utility>

namespace socc::view {
namespace {
// Sends at most this often: changes in between coalesce (the page redraws at display rate).
constexpr auto kMinInterval = std::chrono::milliseconds(100);
}  // namespace

ClientSession::ClientSession(ViewModel& model, FrameWriter writer)
    : model_(model), writer_(std::move(writer)) {}

ClientSession::~ClientSession() {
  stop();
}

void ClientSession::start() {
  model_.addListener(this);
  // Everything the model holds now (changes from here on arrive as listener calls).
  std::vector<BlockKey> keys = model_.read([](const ViewModel& m) {
    std::vector<BlockKey> all;
    all.reserve(m.blocks().size());
    for (const auto& entry : m.blocks()) all.push_back(entry.first);
    return all;
  });
  blocksChanged(keys);
  robotsChanged();
  statsChanged();
  thread_ = std::thread([this] { run(); });
}

void ClientSession::stop() {
  if (!thread_.joinable()) return;
  model_.removeListener(this);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void ClientSession::mapReset() {
  const std::lock_guard<std::mutex> lock(mutex_);
  dirty_.reset = true;
  dirty_.blocks.clear();
  dirty_.robots = true;
  cv_.notify_all();
}

void ClientSession::blocksChanged(const std::vector<BlockKey>& keys) {
  const std::lock_guard<std::mutex> lock(mutex_);
  dirty_.blocks.insert(keys.begin(), keys.end());
  cv_.notify_all();
}

void ClientSession::robotsChanged() {
  const std::lock_guard<std::mutex> lock(mutex_);
  dirty_.robots = true;
  cv_.notify_all();
}

void ClientSession::statsChanged() {
  const std::lock_guard<std::mutex> lock(mutex_);
  dirty_.stats = true;
  cv_.notify_all();
}

void ClientSession::wake() {
  const std::lock_guard<std::mutex> lock(mutex_);
  woken_ = true;
  cv_.notify_all();
}

bool ClientSession::write(bool binary, const void* data, std::size_t size) {
  if (stop_ || !writer_(binary, data, size)) return false;
  bytes_sent_ += size;
  return true;
}

void ClientSession::run() {
  if (!greet()) return;
  while (!stop_) {
    Dirty dirty;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return stop_ || woken_ || !dirty_.empty(); });
      if (stop_) return;
      std::swap(dirty, dirty_);
      woken_ = false;
    }
    if (!send(dirty)) return;
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, kMinInterval, [this] { return stop_.load(); });
  }
}

}  // namespace socc::view
