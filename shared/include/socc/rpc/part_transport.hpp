#pragma once
// Large messages over a lossy LAN (docs/fleet.md, "Large messages"). LCM sends a message of
// 1.6 MB as ~25 UDP datagrams of up to 64 KB, i.e. ~1100 IP fragments, and loses all of it when
// one fragment is lost. PartTransport publishes such a message as part_t messages on
// <channel>/PART, each small enough for one IP packet, keeps them for a while and publishes
// again the parts a receiver asks for (part_nack_t on SOCC/PART_NACK/<endpoint>). Receiving,
// it reassembles the parts (PartAssembler) and hands whole messages to the channel's handler.
// Threads: publish() from any thread; the LCM callbacks and poll() on the thread that handles
// this LCM instance.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <list>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "socc/rpc/part_assembler.hpp"

namespace lcm {
class LCM;
}
struct _lcm_recv_buf_t;
struct _lcm_subscription_t;

namespace socc::rpc {

struct PartOptions {
  bool split = false;                    // send large messages as parts (LAN mode)
  std::size_t part_bytes = 1200;         // payload per part: one IP packet at MTU 1500
  std::chrono::milliseconds keep{3000};  // sent parts are kept this long for NACKs
  std::size_t keep_bytes = 64u << 20;    // and at most this many bytes of them
  PartAssemblerLimits receive;
};

class PartTransport {
 public:
  using Deliver = std::function<void(const std::uint8_t* data, std::size_t size)>;

  /// endpoint_prefix names this process in NACK channels (a random suffix is added).
  PartTransport(lcm::LCM& lcm, const std::string& endpoint_prefix, PartOptions options);
  ~PartTransport();
  PartTransport(const PartTransport&) = delete;
  PartTransport& operator=(const PartTransport&) = delete;

  /// Publishes bytes on channel, as parts on channel/PART when splitting and larger than a
  /// part. Returns 0 on success (as lcm publish).
  int publish(const std::string& channel, const std::uint8_t* data, std::size_t size);
  /// Whole messages sent as parts to channel go to deliver (on the LCM thread).
  void subscribe(const std::string& channel, Deliver deliver);
  /// Asks the senders of stalled transfers for their missing parts; call every few ms.
  void poll();

  const std::string& endpoint() const { return endpoint_; }
  /// Parts published again because a receiver asked for them.
  std::int64_t resentParts() const { return resent_parts_.load(); }

 private:
  struct Route {
    PartTransport* self = nullptr;
    Deliver deliver;
    _lcm_subscription_t* subscription = nullptr;
  };
  struct Sent {
    std::string channel;
    std::vector<std::vector<std::uint8_t>> parts;  // encoded part_t
    std::chrono::steady_clock::time_point at;
    std::size_t bytes = 0;
  };
  static void onPart(const _lcm_recv_buf_t* rbuf, const char* channel, void* route);
  static void onNack(const _lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void remember(std::int64_t transfer_id, Sent sent);
  void resend(const part_nack_t& nack);

  lcm::LCM& lcm_;
  PartOptions options_;
  std::string endpoint_;
  std::atomic<std::int64_t> next_transfer_id_;
  std::atomic<std::int64_t> resent_parts_{0};
  std::mutex sent_mutex_;
  std::map<std::int64_t, Sent> sent_;  // by transfer id (increasing = oldest first)
  std::size_t sent_bytes_ = 0;
  PartAssembler assembler_;
  std::list<Route> routes_;  // stable addresses: the callbacks' user data
  _lcm_subscription_t* nack_subscription_ = nullptr;
};

}  // namespace socc::rpc
