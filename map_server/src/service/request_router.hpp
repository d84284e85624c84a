#pragma once
// LCM side of the service: subscribes to SOCC/<SERVICE>/REQ, turns raw bytes into requests
// (wire guard + checked decode), checks the header (client id, reply channel), passes the
// RequestGate, calls the MapService handler and publishes the reply immediately on
// SOCC/<SERVICE>/REP/<client_id>. Runs on the thread that calls lcm.handle*(): map access
// stays serial.
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <string_view>

#include "map_service.hpp"
#include "rate_limited_log.hpp"
#include "request_gate.hpp"
#include "socc/channels.hpp"

namespace socc::service {

class RequestRouter {
 public:
  RequestRouter(lcm::LCM& lcm, MapService& service, RequestGate& gate, bool verbose);
  ~RequestRouter();
  RequestRouter(const RequestRouter&) = delete;
  RequestRouter& operator=(const RequestRouter&) = delete;

  const RequestCounters& counters() const { return counters_; }
  /// Publishes map_stats_t on SOCC/STATUS.
  void publishStatus();

 private:
  template <typename Request, typename Handler>
  void serve(const lcm::ReceiveBuffer& rbuf, std::string_view service, bool state_changing,
             Handler&& handler);
  template <typename Reply>
  void publishReply(std::string_view service, const request_header_t& request, Reply& reply);
  void rejectUndecodable(std::string_view service, const std::string& why);

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
  std::array<Route, channels::kServices.size()> routes_;
};

}  // namespace socc::service
