#include "socc/rpc/map_client.hpp"

#include <atomic>
#include <condition_variable>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <vector>

#include "socc/auth/message_auth.hpp"
#include "socc/channels.hpp"
#include "socc/keyframes_request_t.hpp"
#include "socc/lcm_url.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/robot_pose_request_t.hpp"
#include "socc/rpc/client_id.hpp"
#include "socc/rpc/part_transport.hpp"
#include "socc/rpc/resend_rule.hpp"
#include "socc/rpc/safe_decode.hpp"
#include "socc/stats_request_t.hpp"
#include "socc/wall_clock.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::rpc {
namespace {

// Every reply starts with its 8-byte type hash followed by reply_header_t, whose first field
// is the int64 request_id (big endian). Peeking it routes raw bytes without knowing the type.
std::optional<std::int64_t> peekRequestId(const lcm::ReceiveBuffer& rbuf) {
  if (rbuf.data_size < 16) return std::nullopt;
  const auto* bytes = static_cast<const std::uint8_t*>(rbuf.data);
  std::uint64_t id = 0;
  for (int i = 8; i < 16; ++i) id = (id << 8) | bytes[i];
  return static_cast<std::int64_t>(id);
}

}  // namespace

struct MapClient::Impl {
  explicit Impl(ClientOptions opts)
      : options(std::move(opts)),
        lcm(options.lcm_url),
        parts(lcm, options.client_id, partOptions()) {
    if (!options.key_file.empty()) key = auth::SharedKey::fromFile(options.key_file);
  }

  // On a LAN, large requests travel in parts that survive packet loss (part_transport.hpp).
  PartOptions partOptions() const {
    PartOptions part_options;
    part_options.split = isLanLcmUrl(options.lcm_url);
    return part_options;
  }

  ClientOptions options;
  lcm::LCM lcm;
  PartTransport parts;                 // publishes requests, reassembles replies sent in parts
  std::optional<auth::SharedKey> key;  // set: every attempt is signed
  // Held from taking a counter until the request is published: calls from several threads
  // must reach the server in counter order, or the later-published one is refused as stale.
  std::mutex send_mutex;
  auth::AuthCounter auth_counter;
  std::mutex mutex;
  std::condition_variable arrived;
  // request_id -> reply bytes (empty until the reply arrives). Only ids in here are kept,
  // so late duplicates of an answered request are dropped.
  std::unordered_map<std::int64_t, std::vector<std::uint8_t>> pending;
  std::atomic<std::int64_t> next_request_id{0};
  std::atomic<bool> answered{false};  // a reply to one of this client's requests arrived
  std::atomic<bool> stop{false};
  std::thread receiver;

  // LCM C API callback (the C++ raw-handler wrapper trips UBSan's vptr check).
  static void onReply(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
    static_cast<Impl*>(self)->store(
        lcm::ReceiveBuffer{rbuf->data, rbuf->data_size, rbuf->recv_utime});
  }

  void store(const lcm::ReceiveBuffer& rbuf) {
    const auto id = peekRequestId(rbuf);
    if (!id) return;
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = pending.find(*id);
    if (it == pending.end() || !it->second.empty()) return;
    const auto* bytes = static_cast<const std::uint8_t*>(rbuf.data);
    it->second.assign(bytes, bytes + rbuf.data_size);
    answered.store(true);
    arrived.notify_all();
  }

  // Short waits: stalled replies in parts are asked for again within ~10 ms of the stall.
  void receiveLoop() {
    while (!stop.load()) {
      lcm.handleTimeout(10);
      parts.poll();
    }
  }

  // Call with send_mutex held. A fresh counter per attempt: the server refuses a reused one
  // as a replay, so a retry cannot be the same bytes (request_id and seq stay the same).
  template <typename Request>
  std::string encodeAttempt(Request& request, std::vector<std::uint8_t>& bytes) {
    request.header.auth_counter = 0;
    request.header.mac_len = 0;
    request.header.mac.clear();
    if (key) {
      try {
        auth::sign(request, *key, auth_counter.next());
      } catch (const std::exception& e) {
        return e.what();
      }
    }
    bytes.resize(static_cast<std::size_t>(request.getEncodedSize()));
    if (request.encode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0)
      return "request cannot be encoded";
    return {};
  }

  template <typename Reply, typename Request>
  Result<Reply> call(std::string_view service, Request& request) {
    return call<Reply>(service, request, options.timeout);
  }

  // Refusals that applied nothing and invite the same request again (resend_rule.hpp): it is
  // sent again after the rule's pause, so a client replaying data faster than the server's
  // per-robot limit slows down instead of failing, and a search waits for a free searcher.
  template <typename Reply, typename Request>
  Result<Reply> call(std::string_view service, Request& request, std::chrono::milliseconds timeout,
                     std::initializer_list<ResendRule> rules = {kRateLimitedRule}) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<int> refusals(rules.size(), 0);
    for (;;) {
      Result<Reply> result = callOnce<Reply>(service, request, timeout);
      const int which = matchingRule(result.error.status, result.error.message, rules);
      if (which < 0) return result;
      const ResendRule& rule = rules.begin()[which];
      const auto pause = rule.pause(++refusals[static_cast<std::size_t>(which)]);
      if (std::chrono::steady_clock::now() + pause > start + rule.within) return result;
      std::this_thread::sleep_for(pause);
    }
  }

  template <typename Reply, typename Request>
  Result<Reply> callOnce(std::string_view service, Request& request,
                         std::chrono::milliseconds timeout) {
    request.header.request_id = next_request_id.fetch_add(1);
    request.header.client_id = options.client_id;
    request.header.reply_channel = channels::reply(service, options.client_id);
    request.header.utime = nowMicros();
    const std::string channel = channels::request(service);
    const std::int64_t id = request.header.request_id;

    Result<Reply> result;
    std::unique_lock<std::mutex> lock(mutex);
    pending.emplace(id, std::vector<std::uint8_t>{});
    for (int attempt = 1; attempt <= std::max(1, options.max_attempts); ++attempt) {
      result.attempts = attempt;
      lock.unlock();
      // The same request (request_id, seq) on every attempt: the server deduplicates Integrate
      // on (client, seq). Encoded per attempt because a signed request must be re-signed.
      std::vector<std::uint8_t> bytes;
      std::unique_lock<std::mutex> send_lock(send_mutex);
      if (const std::string why = encodeAttempt(request, bytes); !why.empty()) {
        send_lock.unlock();
        const std::lock_guard<std::mutex> relock(mutex);
        pending.erase(id);
        result.error = {reply_header_t::INVALID_ARGUMENT, why, false};
        return result;
      }
      parts.publish(channel, bytes.data(), bytes.size());
      send_lock.unlock();
      lock.lock();
      if (arrived.wait_for(lock, timeout, [&] { return !pending[id].empty(); })) break;
    }
    std::vector<std::uint8_t> raw = std::move(pending[id]);
    pending.erase(id);
    lock.unlock();

    if (raw.empty()) {
      result.error = {reply_header_t::INTERNAL,
                      "no reply on " + channels::reply(service, options.client_id) + " after " +
                          std::to_string(result.attempts) +
                          " attempt(s) (is map_server running on " + options.lcm_url + "?)",
                      true};
      return result;
    }
    result.bytes_received = static_cast<std::int64_t>(raw.size());
    auto reply = safeDecode<Reply>(raw.data(), static_cast<int>(raw.size()));
    if (!reply) {
      result.error = {reply_header_t::INTERNAL, "undecodable reply on " + std::string(service),
                      false};
      return result;
    }
    if (reply->header.status != reply_header_t::OK) {
      result.error = {reply->header.status, reply->header.message, false};
      return result;
    }
    result.reply = std::move(reply);
    return result;
  }
};

MapClient::MapClient(ClientOptions options) {
  if (const std::string why = checkLcmUrl(options.lcm_url, lcmAuthFor(options.key_file));
      !why.empty())
    throw std::runtime_error(why);
  if (const std::string why = checkClientId(options.client_id); !why.empty())
    throw std::runtime_error(why);
  impl_ = std::make_unique<Impl>(std::move(options));
  if (!impl_->lcm.good())
    throw std::runtime_error("cannot open LCM on " + impl_->options.lcm_url +
                             " (is multicast routed to lo? see scripts/setup.sh)");
  // Random start so two processes sharing a client id do not reuse each other's ids.
  std::random_device rd;
  impl_->next_request_id = static_cast<std::int64_t>(
      ((static_cast<std::uint64_t>(rd()) << 31) ^ rd()) & 0x3fffffffffffffffULL);
  for (const auto service : channels::kServices) {
    const std::string reply_channel = channels::reply(service, impl_->options.client_id);
    lcm_subscribe(impl_->lcm.getUnderlyingLCM(), reply_channel.c_str(), &Impl::onReply,
                  impl_.get());
    impl_->parts.subscribe(reply_channel,
                           [impl = impl_.get()](const std::uint8_t* data, std::size_t size) {
                             impl->store(lcm::ReceiveBuffer{const_cast<std::uint8_t*>(data),
                                                            static_cast<std::uint32_t>(size), 0});
                           });
  }
  impl_->receiver = std::thread([impl = impl_.get()] { impl->receiveLoop(); });
}

MapClient::~MapClient() {
  impl_->stop = true;
  if (impl_->receiver.joinable()) impl_->receiver.join();
}

const ClientOptions& MapClient::options() const {
  return impl_->options;
}

bool MapClient::answered() const {
  return impl_->answered.load();
}

Result<integrate_reply_t> MapClient::integrate(integrate_request_t request) {
  // encode() trusts the counts: rows of the wrong length would be read out of bounds.
  if (const std::string why = wire::checkArrays(request); !why.empty()) {
    Result<integrate_reply_t> refused;
    refused.error = {reply_header_t::INVALID_ARGUMENT, why, false};
    return refused;
  }
  return impl_->call<integrate_reply_t>(channels::kIntegrate, request);
}
Result<chunk_reply_t> MapClient::getChunk(chunk_request_t request) {
  return impl_->call<chunk_reply_t>(channels::kGetChunk, request);
}
Result<stats_reply_t> MapClient::getStats() {
  stats_request_t request;
  return impl_->call<stats_reply_t>(channels::kGetStats, request);
}
Result<robot_pose_reply_t> MapClient::getRobotPose(const std::string& robot_id,
                                                   std::int32_t max_history,
                                                   std::int64_t history_from_seq) {
  robot_pose_request_t request{};
  request.robot_id = robot_id;
  request.max_history = max_history;
  request.history_from_seq = history_from_seq;
  return impl_->call<robot_pose_reply_t>(channels::kGetRobotPose, request);
}
Result<keyframes_reply_t> MapClient::getKeyframes(const std::string& robot_id,
                                                  std::int64_t from_seq,
                                                  std::int32_t max_keyframes) {
  keyframes_request_t request{};
  request.robot_id = robot_id;
  request.from_seq = from_seq;
  request.max_keyframes = max_keyframes;
  return impl_->call<keyframes_reply_t>(channels::kGetKeyframes, request);
}
Result<map_command_reply_t> MapClient::command(map_command_request_t request) {
  return impl_->call<map_command_reply_t>(channels::kMapCommand, request);
}
Result<render_reply_t> MapClient::render(render_request_t request) {
  return impl_->call<render_reply_t>(channels::kRender, request);
}
Result<robot_status_reply_t> MapClient::reportTracking(std::int8_t tracking_state,
                                                       const std::string& reason, std::int64_t seq,
                                                       std::int64_t utime) {
  robot_status_request_t request{};
  request.seq = seq;
  request.utime = utime;
  request.tracking_state = tracking_state;
  request.reason = reason;
  return impl_->call<robot_status_reply_t>(channels::kRobotStatus, request);
}

Result<localize_reply_t> MapClient::localize(localize_request_t request) {
  if (const std::string why = wire::checkArrays(request); !why.empty()) {
    Result<localize_reply_t> refused;
    refused.error = {reply_header_t::INVALID_ARGUMENT, why, false};
    return refused;
  }
  // A search (and, after the map grew, a rebuild of its descriptors) takes seconds.
  constexpr std::chrono::milliseconds kLocalizeTimeout{30000};
  const auto timeout = std::max(impl_->options.timeout, kLocalizeTimeout);
  return impl_->call<localize_reply_t>(channels::kLocalize, request, timeout,
                                       {kRateLimitedRule, searchesBusyRule(timeout)});
}

chunk_request_t sphereChunkRequest(const Eigen::Vector3d& center, double radius,
                                   std::int32_t fields) {
  chunk_request_t request{};
  request.shape = chunk_request_t::SHAPE_SPHERE;
  for (int i = 0; i < 3; ++i) request.center[i] = center[i];
  request.radius = radius;
  request.occupancy_threshold = 0.5f;
  request.fields = fields;
  request.limit = 0;
  return request;
}

localize_request_t makeLocalizeRequest(const std::vector<Eigen::Vector3f>& points,
                                       std::int32_t max_candidates) {
  localize_request_t request{};
  request.num_points = static_cast<std::int32_t>(points.size());
  request.xyz.resize(3);
  for (int axis = 0; axis < 3; ++axis) {
    request.xyz[axis].resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) request.xyz[axis][i] = points[i][axis];
  }
  request.hint_yaw_tolerance = M_PI;
  request.max_candidates = max_candidates;
  return request;
}

integrate_request_t makeIntegrateRequest(std::int64_t seq, std::int64_t scan_utime,
                                         const Eigen::Isometry3d& sensor_pose,
                                         const LabeledCloud& cloud,
                                         const std::optional<GravityReference>& gravity) {
  integrate_request_t request{};
  request.seq = seq;
  request.scan_utime = scan_utime;
  request.sensor_pose = toLcm(sensor_pose);
  request.num_points = static_cast<std::int32_t>(cloud.size());
  request.xyz_resolution = wire::quantizePoints(cloud.points, request.xyz);
  request.num_labels = static_cast<std::int32_t>(cloud.labels.size());
  request.label.assign(cloud.labels.begin(), cloud.labels.end());
  request.num_times = static_cast<std::int32_t>(cloud.times.size());
  request.time = cloud.times;
  if (gravity) {  // else gravity_sigma stays 0: no reference
    const Eigen::Vector3d up = gravity->up.normalized();
    for (int i = 0; i < 3; ++i) request.gravity_up[i] = static_cast<float>(up[i]);
    request.gravity_sigma = static_cast<float>(gravity->sigma);
  }
  return request;
}

}  // namespace socc::rpc
