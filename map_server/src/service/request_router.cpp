#include "request_router.hpp"

#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "socc/channels.hpp"
#include "socc/rpc/client_id.hpp"
#include "socc/rpc/safe_decode.hpp"
#include "socc/rpc/status_names.hpp"
#include "socc/wall_clock.hpp"
#include "wire_guard.hpp"

namespace socc::service {
namespace {

rpc::PartOptions partOptions(bool split) {
  rpc::PartOptions options;
  options.split = split;
  return options;
}

// A handler's result: its reply, or (std::optional) none yet when the reply is deferred.
template <typename Result>
struct ReplyOf {
  using type = Result;
  static std::optional<type> now(Result&& result) { return std::move(result); }
};
template <typename Reply>
struct ReplyOf<std::optional<Reply>> {
  using type = Reply;
  static std::optional<type> now(std::optional<Reply>&& result) { return std::move(result); }
};

// Untrusted strings are shortened before they reach logs or reply messages.
std::string shown(const std::string& text) {
  return text.size() > 80 ? text.substr(0, 80) + "..." : text;
}

}  // namespace

RequestRouter::RequestRouter(lcm::LCM& lcm, MapService& service, RequestGate& gate, bool verbose,
                             bool split_large_replies)
    : lcm_(lcm),
      service_(service),
      gate_(gate),
      log_(verbose),
      parts_(lcm, "map_server", partOptions(split_large_replies)),
      integrate_rate_(service.config().limits.robot_integrate_rate,
                      service.config().limits.robot_integrate_rate),
      chunk_rate_(service.config().limits.robot_chunk_rate,
                  service.config().limits.robot_chunk_rate),
      searches_(static_cast<std::size_t>(service.config().limits.max_waiting_searches)) {
  // Raw subscriptions through LCM's C API: the typed C++ ones print and drop undecodable
  // messages without telling us, and the C++ raw-handler wrapper trips UBSan (-fsanitize=vptr).
  for (std::size_t i = 0; i < routes_.size(); ++i) {
    routes_[i].router = this;
    routes_[i].service = channels::kServices[i];
    routes_[i].subscription =
        lcm_subscribe(lcm_.getUnderlyingLCM(), channels::request(channels::kServices[i]).c_str(),
                      &RequestRouter::onMessage, &routes_[i]);
    // The same request sent in parts (a client on a LAN), reassembled.
    parts_.subscribe(
        channels::request(channels::kServices[i]),
        [this, service = routes_[i].service](const std::uint8_t* data, std::size_t size) {
          dispatch(service, lcm::ReceiveBuffer{const_cast<std::uint8_t*>(data),
                                               static_cast<std::uint32_t>(size), 0});
        });
  }
}

RequestRouter::~RequestRouter() {
  for (const Route& route : routes_)
    if (route.subscription != nullptr) lcm_unsubscribe(lcm_.getUnderlyingLCM(), route.subscription);
}

void RequestRouter::onMessage(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* route) {
  const auto* r = static_cast<const Route*>(route);
  const lcm::ReceiveBuffer buffer{rbuf->data, rbuf->data_size, rbuf->recv_utime};
  r->router->dispatch(r->service, buffer);
}

std::string RequestRouter::admitRate(std::string_view service, const std::string& client) {
  const bool integrate = service == channels::kIntegrate;
  if (!integrate && service != channels::kGetChunk) return {};
  RobotRateLimiter& limiter = integrate ? integrate_rate_ : chunk_rate_;
  if (limiter.admit(client, std::chrono::steady_clock::now())) return {};
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%g", limiter.rate());
  return "'" + client + "' exceeds its " + rate + " " + std::string(service) +
         " requests/s (limits." + (integrate ? "robot_integrate_rate" : "robot_chunk_rate") +
         "): " + std::string(rpc::kRateLimited);
}

void RequestRouter::rejectUndecodable(std::string_view service, const std::string& why) {
  ++counters_.decode_failures;
  ++counters_.rejected;
  log_.warn("dropped undecodable " + std::string(service) + " request: " + why);
}

template <typename Reply>
void RequestRouter::publishReply(std::string_view service, const request_header_t& request,
                                 Reply& reply) {
  reply.header.request_id = request.request_id;
  reply.header.client_id = request.client_id;
  reply.header.server_utime = nowMicros();
  if (reply.header.status != reply_header_t::OK) {
    ++counters_.rejected;
    log_.warn(std::string(service) + " from '" + request.client_id +
              "' rejected: " + reply.header.message);
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(reply.getEncodedSize()));
  reply.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  // Only ever to the requester's own reply channel, whatever the request asked for.
  std::string channel = channels::reply(service, request.client_id);
  // An accepted INTEGRATE is acknowledged only once its journal entry is on stable storage.
  if (service == channels::kIntegrate && reply.header.status == reply_header_t::OK &&
      service_.acksWaitForSync()) {
    deferred_.push_back({std::move(channel), std::move(bytes)});
    return;
  }
  send(service, channel, bytes);
}

void RequestRouter::send(std::string_view service, const std::string& channel,
                         const std::vector<std::uint8_t>& bytes) {
  if (parts_.publish(channel, bytes.data(), bytes.size()) != 0)
    log_.warn("cannot publish a " + std::to_string(bytes.size()) + "-byte " + std::string(service) +
              " reply (larger than LCM allows? lower limits.max_reply_bytes)");
}

void RequestRouter::commit() {
  if (deferred_.empty()) return;
  service_.syncJournal();
  for (const DeferredReply& reply : deferred_)
    send(channels::kIntegrate, reply.channel, reply.bytes);
  deferred_.clear();
}

template <typename Request, typename Handler>
void RequestRouter::serve(const lcm::ReceiveBuffer& rbuf, std::string_view service,
                          bool state_changing, Handler&& handler) {
  using Result = std::invoke_result_t<Handler, const Request&>;
  using Reply = typename ReplyOf<Result>::type;
  ++counters_.requests;
  const int size = static_cast<int>(rbuf.data_size);
  const bool integrate = service == channels::kIntegrate;
  if (const std::string why =
          integrate ? checkIntegrateWire(rbuf.data, size) : checkRequestHeaderWire(rbuf.data, size);
      !why.empty())
    return rejectUndecodable(service, why);
  const std::optional<Request> request = rpc::safeDecode<Request>(rbuf.data, size);
  if (!request) return rejectUndecodable(service, "LCM decode failed (wrong type or damaged)");

  const request_header_t& header = request->header;
  if (const std::string why = rpc::checkClientId(header.client_id); !why.empty()) {
    // Without a valid client id there is no safe channel to answer on.
    ++counters_.rejected;
    log_.warn("ignored " + std::string(service) + " request: " + shown(why));
    return;
  }
  Reply reply{};
  if (header.reply_channel != channels::reply(service, header.client_id)) {
    setStatus(reply, Status::invalid("reply_channel must be " +
                                     channels::reply(service, header.client_id)));
    return publishReply(service, header, reply);
  }
  // The one place every request is admitted (authentication goes here).
  if (const std::string why = gate_.admit(service, state_changing, header,
                                          static_cast<const std::uint8_t*>(rbuf.data), size);
      !why.empty()) {
    ++counters_.auth_failures;
    setStatus(reply, Status::unauthenticated(why));
    return publishReply(service, header, reply);
  }
  // Fairness: after authentication, so a forger cannot spend a robot's budget.
  if (const std::string why = admitRate(service, header.client_id); !why.empty()) {
    setStatus(reply, Status::exhausted(why));
    return publishReply(service, header, reply);
  }
  try {
    std::optional<Reply> now = ReplyOf<Result>::now(handler(*request));
    if (!now) return;  // deferred: published later
    reply = std::move(*now);
  } catch (const std::exception& e) {
    reply = Reply{};
    setStatus(reply, Status::internal(e.what()));
  }
  publishReply(service, header, reply);
}

void RequestRouter::dispatch(std::string_view service, const lcm::ReceiveBuffer& rbuf) {
  if (service == channels::kIntegrate)
    // serve() decodes with safeDecode, which uses all of rbuf: these are r's bytes exactly.
    serve<integrate_request_t>(rbuf, service, true, [this, &rbuf](const integrate_request_t& r) {
      return service_.integrate(r, static_cast<const std::uint8_t*>(rbuf.data), rbuf.data_size);
    });
  else if (service == channels::kGetChunk)
    serve<chunk_request_t>(rbuf, service, false,
                           [this](const chunk_request_t& r) { return service_.getChunk(r); });
  else if (service == channels::kGetStats)
    serve<stats_request_t>(rbuf, service, false, [this](const stats_request_t& r) {
      return service_.getStats(r, counters_);
    });
  else if (service == channels::kGetRobotPose)
    serve<robot_pose_request_t>(rbuf, service, false, [this](const robot_pose_request_t& r) {
      return service_.getRobotPose(r);
    });
  else if (service == channels::kMapCommand)
    serve<map_command_request_t>(rbuf, service, true, [this](const map_command_request_t& r) {
      return service_.command(r);
    });
  else if (service == channels::kRender)
    serve<render_request_t>(rbuf, service, false,
                            [this](const render_request_t& r) { return service_.render(r); });
  else if (service == channels::kRobotStatus)
    // State-changing: a LOST report stops the robot's integrations.
    serve<robot_status_request_t>(rbuf, service, true, [this](const robot_status_request_t& r) {
      return service_.robotStatus(r);
    });
  else if (service == channels::kGetKeyframes)
    serve<keyframes_request_t>(rbuf, service, false, [this](const keyframes_request_t& r) {
      return service_.getKeyframes(r);
    });
  else if (service == channels::kLocalize)
    serve<localize_request_t>(rbuf, service, false,
                              [this](const localize_request_t& r) { return startLocalize(r); });
}

std::optional<localize_reply_t> RequestRouter::startLocalize(const localize_request_t& request) {
  std::pair<std::string, std::int64_t> key{request.header.client_id, request.header.request_id};
  if (searching_.count(key) != 0) {
    log_.warn("LOCALIZE " + std::to_string(key.second) + " from '" + key.first +
              "' repeated while its search is under way: answered once it ends");
    return std::nullopt;
  }
  std::variant<localize_reply_t, MapService::PendingLocalize> begun =
      service_.beginLocalize(request, searches_.hasRoom());
  if (auto* now = std::get_if<localize_reply_t>(&begun)) return std::move(*now);
  // std::function needs copyable jobs: the search is shared between job and continuation.
  auto pending = std::make_shared<MapService::PendingLocalize>(
      std::get<MapService::PendingLocalize>(std::move(begun)));
  // Cannot be refused: beginLocalize was told there is room, and only this thread submits.
  searches_.submit([this, pending, header = request.header](const std::atomic<bool>& cancelled) {
    pending->run(&cancelled);  // the worker: no grid, no LCM
    return BackgroundWorker::Continuation([this, pending, header] {
      searching_.erase({header.client_id, header.request_id});
      localize_reply_t reply = service_.finishLocalize(std::move(*pending));
      publishReply(channels::kLocalize, header, reply);
    });
  });
  searching_.insert(std::move(key));
  return std::nullopt;
}

void RequestRouter::poll() {
  parts_.poll();
  searches_.runFinished();
}

void RequestRouter::publishStatus() {
  map_stats_t stats = service_.stats(counters_);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(stats.getEncodedSize()));
  stats.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  lcm_.publish(std::string(channels::kStatus), bytes.data(), static_cast<unsigned>(bytes.size()));
}

}  // namespace socc::service
