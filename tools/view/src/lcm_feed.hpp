#pragma once
// socc-view's LCM side: subscribes to what the map server and the robots publish
// (SOCC/MAP_DELTA map_delta_t, SOCC/STATUS map_stats_t, SOCC/INTEGRATE/REQ integrate_request_t)
// and feeds the ViewModel, on its own thread. Undecodable or inconsistent messages are counted
// and dropped. Robots in LAN mode send their scans as parts (docs/fleet.md): those are
// reassembled. Only listens: it never publishes (not even a NACK for a lost part: that scan is
// just not drawn), so it cannot disturb the map server or the robots.
#include <atomic>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

#include "socc/rpc/part_transport.hpp"
#include "view_model.hpp"

namespace socc::view {

class LcmFeed {
 public:
  /// Throws std::runtime_error when LCM cannot be opened on url.
  LcmFeed(const std::string& url, ViewModel& model);
  ~LcmFeed();
  LcmFeed(const LcmFeed&) = delete;
  LcmFeed& operator=(const LcmFeed&) = delete;

  std::int64_t dropped() const { return dropped_; }
  /// Bytes received on SOCC/MAP_DELTA, SOCC/STATUS and SOCC/INTEGRATE/REQ.
  std::int64_t deltaBytes() const { return delta_bytes_; }
  std::int64_t statusBytes() const { return status_bytes_; }
  std::int64_t integrateBytes() const { return integrate_bytes_; }

 private:
  static void onDelta(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void onStatus(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void onIntegrate(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void integrate(const std::uint8_t* data, std::size_t size);
  void run();

  lcm::LCM lcm_;
  rpc::PartTransport parts_;  // receive side only: poll() (NACKs) is never called
  ViewModel& model_;
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<std::int64_t> delta_bytes_{0};
  std::atomic<std::int64_t> status_bytes_{0};
  std::atomic<std::int64_t> integrate_bytes_{0};
  std::thread thread_;
};

}  // namespace socc::view
