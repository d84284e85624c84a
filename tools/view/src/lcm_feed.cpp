#include "lcm_feed.hpp"

#include <iostream>
#include <stdexcept>

#include "socc/channels.hpp"
#include "socc/rpc/client_id.hpp"
#include "socc/rpc/safe_decode.hpp"

namespace socc::view {
namespace {

template <typename Message>
std::optional<Message> decode(const lcm_recv_buf_t* rbuf) {
  return rpc::safeDecode<Message>(rbuf->data, static_cast<int>(rbuf->data_size));
}

}  // namespace

LcmFeed::LcmFeed(const std::string& url, ViewModel& model)
    : lcm_(url), parts_(lcm_, "socc-view", rpc::PartOptions{}), model_(model) {
  if (!lcm_.good())
    throw std::runtime_error("cannot open LCM on " + url +
                             " (multicast routed to lo? `ip route replace 224.0.0.0/4 dev lo`)");
  // Raw C subscriptions: decoding is ours (checked), as in the map server's router.
  lcm_t* raw = lcm_.getUnderlyingLCM();
  lcm_subscribe(raw, std::string(channels::kMapDelta).c_str(), &LcmFeed::onDelta, this);
  lcm_subscribe(raw, std::string(channels::kStatus).c_str(), &LcmFeed::onStatus, this);
  lcm_subscribe(raw, channels::request(channels::kIntegrate).c_str(), &LcmFeed::onIntegrate, this);
  parts_.subscribe(channels::request(channels::kIntegrate),
                   [this](const std::uint8_t* data, std::size_t size) { integrate(data, size); });
  thread_ = std::thread([this] { run(); });
}

LcmFeed::~LcmFeed() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void LcmFeed::run() {
  while (!stop_)
    if (lcm_.handleTimeout(100) < 0) {
      std::cerr << "socc-view: LCM receive failed\n";
      return;
    }
}

void LcmFeed::onDelta(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
  auto* feed = static_cast<LcmFeed*>(self);
  feed->delta_bytes_ += rbuf->data_size;
  const auto delta = decode<map_delta_t>(rbuf);
  if (!delta || !feed->model_.applyDelta(*delta).empty()) ++feed->dropped_;
}

void LcmFeed::onStatus(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
  auto* feed = static_cast<LcmFeed*>(self);
  feed->status_bytes_ += rbuf->data_size;
  const auto stats = decode<map_stats_t>(rbuf);
  if (!stats) return void(++feed->dropped_);
  for (const robot_state_t& r : stats->robots)
    if (!rpc::checkClientId(r.robot_id).empty()) return void(++feed->dropped_);
  feed->model_.applyStats(*stats);
}

void LcmFeed::onIntegrate(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
  static_cast<LcmFeed*>(self)->integrate(static_cast<const std::uint8_t*>(rbuf->data),
                                         rbuf->data_size);
}

void LcmFeed::integrate(const std::uint8_t* data, std::size_t size) {
  integrate_bytes_ += static_cast<std::int64_t>(size);
  const auto request = rpc::safeDecode<integrate_request_t>(data, static_cast<int>(size));
  if (!request || !rpc::checkClientId(request->header.client_id).empty()) return void(++dropped_);
  model_.applyIntegrate(*request);
}

}  // namespace socc::view
