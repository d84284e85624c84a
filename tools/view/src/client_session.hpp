#pragma once
// One WebSocket client of socc-view. The model only marks what changed (blocks, robots, stats)
// in the session's dirty state; the session's own thread turns that into messages and writes
// them. A slow client therefore holds no queue of messages: its dirty state is bounded by the
// map (a block changed ten times is sent once, with its content at sending time), its writes
// block only its own thread, and the LCM side and the map server never wait for it.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "view_model.hpp"

namespace socc::view {

/// Writes one WebSocket message (text or binary); false when the connection is gone.
using FrameWriter = std::function<bool(bool binary, const void* data, std::size_t size)>;

class ClientSession : public ModelListener {
 public:
  ClientSession(ViewModel& model, FrameWriter writer);
  ~ClientSession() override;
  ClientSession(const ClientSession&) = delete;
  ClientSession& operator=(const ClientSession&) = delete;

  /// Registers with the model, marks everything dirty and starts the sender thread.
  void start();
  /// Unregisters and joins the sender thread (the connection must still exist).
  void stop();
  /// A text message from the client.
  virtual void received(const std::string& /*text*/) {}

  std::uint64_t bytesSent() const { return bytes_sent_; }

  // ModelListener: only note what changed.
  void mapReset() override;
  void blocksChanged(const std::vector<BlockKey>& keys) override;
  void robotsChanged() override;
  void statsChanged() override;

 protected:
  /// What to send next, taken from the dirty state under the session's lock.
  struct Dirty {
    bool reset = false;
    std::set<BlockKey> blocks;
    bool robots = false;
    bool stats = false;
    bool empty() const { return !reset && blocks.empty() && !robots && !stats; }
  };
  /// Sends what dirty says (called on the sender thread, no lock held); false ends the session.
  virtual bool send(Dirty& dirty) = 0;
  /// First messages of the session (before any dirty state); false ends it.
  virtual bool greet() { return true; }
  bool write(bool binary, const void* data, std::size_t size);
  bool writeText(const std::string& text) { return write(false, text.data(), text.size()); }
  /// Wakes the sender (e.g. after a subscription changed).
  void wake();
  bool stopping() const { return stop_; }

  ViewModel& model_;

 private:
  void run();

  FrameWriter writer_;
  std::mutex mutex_;
  std::condition_variable cv_;
  Dirty dirty_;
  bool woken_ = false;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> bytes_sent_{0};
  std::thread thread_;
};

}  // namespace socc::view
