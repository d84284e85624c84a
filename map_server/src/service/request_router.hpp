#pragma once
// LCM side of the service: subscribes to SOCC/<SERVICE>/REQ, turns raw bytes into requests
// (wire guard + checked decode), checks the header (client id, reply channel), passes the
// RequestGate, calls the MapService handler and publishes the reply on
// SOCC/<SERVICE>/REP/<client_id>: immediately, except accepted INTEGRATEs while the journal
// syncs in batches (group commit: their replies wait for commit()), and LOCALIZE searches: their
// draws run on the router's search thread (BackgroundWorker) and their replies go out from
// poll(). Everything else runs on the thread that calls lcm.handle*() and poll(): map access
// stays serial.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "background_worker.hpp"
#include "map_service.hpp"
#include "rate_limited_log.hpp"
#include "request_gate.hpp"
#include "robot_rate_limiter.hpp"
#include "socc/channels.hpp"
#include "socc/rpc/part_transport.hpp"

namespace socc::service {

class RequestRouter {
 public:
  /// split_large_replies: LAN mode, large replies go out in parts (socc/rpc/part_transport.hpp);
  /// requests sent in parts are received in any mode.
  RequestRouter(lcm::LCM& lcm, MapService& service, RequestGate& gate, bool verbose,
                bool split_large_replies = false);
  ~RequestRouter();
  RequestRouter(const RequestRouter&) = delete;
  RequestRouter& operator=(const RequestRouter&) = delete;

  const RequestCounters& counters() const { return counters_; }
  /// Publishes map_stats_t on SOCC/STATUS.
  void publishStatus();
  /// Group commit: syncs the journal once for the INTEGRATEs accepted since the last call, then
  /// publishes their replies. Call after every batch of handled requests. Throws
  /// std::runtime_error when the sync fails (the replies are not sent).
  void commit();
  /// Replies waiting for commit().
  std::size_t deferredReplies() const { return deferred_.size(); }
  /// Asks for the missing parts of stalled requests sent in parts and publishes the replies of
  /// finished LOCALIZE searches; call every few ms.
  void poll();
  /// LOCALIZE searches accepted whose reply has not gone out yet.
  std::size_t searchesUnderWay() const { return searches_.outstanding(); }

 private:
  template <typename Request, typename Handler>
  void serve(const lcm::ReceiveBuffer& rbuf, std::string_view service, bool state_changing,
             Handler&& handler);
  template <typename Reply>
  void publishReply(std::string_view service, const request_header_t& request, Reply& reply);
  void rejectUndecodable(std::string_view service, const std::string& why);
  /// The reply now, or nullopt when a search was queued (or is under way already for this
  /// request: a client's retry) and poll() replies later.
  std::optional<localize_reply_t> startLocalize(const localize_request_t& request);
  /// Empty when client is within its budget for service, else the RESOURCE_EXHAUSTED message.
  std::string admitRate(std::string_view service, const std::string& client);
  void send(std::string_view service, const std::string& channel,
            const std::vector<std::uint8_t>& bytes);

  void dispatch(std::string_view service, const lcm::ReceiveBuffer& rbuf);
  static void onMessage(const lcm_recv_buf_t* rbuf, const char* channel, void* route);

  // One per service; its address is the C callback's user data.
  struct Route {
    RequestRouter* router = nullptr;
    std::string_view service;
    lcm_subscription_t* subscription = nullptr;
  };

  lcm::LCM& lcm_;
  MapService& service_;
  RequestGate& gate_;
  RequestCounters counters_;
  RateLimitedLog log_;
  struct DeferredReply {
    std::string channel;
    std::vector<std::uint8_t> bytes;
  };
  std::vector<DeferredReply> deferred_;  // INTEGRATE acks waiting for the journal's sync
  rpc::PartTransport parts_;
  RobotRateLimiter integrate_rate_;  // per robot: fairness (limits.robot_integrate_rate)
  RobotRateLimiter chunk_rate_;      // limits.robot_chunk_rate
  std::array<Route, channels::kServices.size()> routes_;
  // (client id, request id) of the searches queued or running: a retry is not searched twice.
  std::set<std::pair<std::string, std::int64_t>> searching_;
  BackgroundWorker searches_;  // last: destroyed (cancelled, joined) before what jobs reply with
};

}  // namespace socc::service
