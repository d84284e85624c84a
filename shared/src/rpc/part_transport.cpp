#include "socc/rpc/part_transport.hpp"

#include <algorithm>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <random>

#include "socc/rpc/safe_decode.hpp"

namespace socc::rpc {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kPartSuffix = "/PART";
constexpr const char* kNackPrefix = "SOCC/PART_NACK/";
// Queued parts per subscription before LCM drops them (its default is 30 messages): a 1.6 MB
// message is ~1300 parts, and the receiving thread may be busy for a while.
constexpr int kPartQueue = 20000;

template <typename Message>
std::vector<std::uint8_t> encoded(const Message& message) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

std::string randomSuffix() {
  std::random_device rd;
  char text[16];
  std::snprintf(text, sizeof(text), "%08x", static_cast<unsigned>(rd()));
  return text;
}

}  // namespace

PartTransport::PartTransport(lcm::LCM& lcm, const std::string& endpoint_prefix, PartOptions options)
    : lcm_(lcm),
      options_(options),
      endpoint_(endpoint_prefix + "." + randomSuffix()),
      next_transfer_id_(static_cast<std::int64_t>(std::random_device{}()) << 20),
      assembler_(options.receive) {
  options_.part_bytes = std::max<std::size_t>(options_.part_bytes, 64);
  nack_subscription_ = lcm_subscribe(lcm_.getUnderlyingLCM(), (kNackPrefix + endpoint_).c_str(),
                                     &PartTransport::onNack, this);
}

PartTransport::~PartTransport() {
  lcm_unsubscribe(lcm_.getUnderlyingLCM(), nack_subscription_);
  for (Route& route : routes_) lcm_unsubscribe(lcm_.getUnderlyingLCM(), route.subscription);
}

int PartTransport::publish(const std::string& channel, const std::uint8_t* data, std::size_t size) {
  if (!options_.split || size <= options_.part_bytes)
    return lcm_.publish(channel, data, static_cast<unsigned>(size));
  part_t part{};
  part.sender = endpoint_;
  part.transfer_id = next_transfer_id_.fetch_add(1);
  part.count = static_cast<std::int32_t>((size + options_.part_bytes - 1) / options_.part_bytes);
  part.total_size = static_cast<std::int32_t>(size);
  Sent sent;
  sent.channel = channel + kPartSuffix;
  int rc = 0;
  for (part.index = 0; part.index < part.count; ++part.index) {
    part.offset = part.index * static_cast<std::int32_t>(options_.part_bytes);
    part.size = static_cast<std::int32_t>(
        std::min<std::size_t>(options_.part_bytes, size - static_cast<std::size_t>(part.offset)));
    part.data.assign(data + part.offset, data + part.offset + part.size);
    sent.parts.push_back(encoded(part));
    const auto& bytes = sent.parts.back();
    rc =
        std::min(rc, lcm_.publish(sent.channel, bytes.data(), static_cast<unsigned>(bytes.size())));
    sent.bytes += bytes.size();
  }
  remember(part.transfer_id, std::move(sent));
  return rc;
}

void PartTransport::remember(std::int64_t transfer_id, Sent sent) {
  const std::lock_guard<std::mutex> lock(sent_mutex_);
  sent.at = Clock::now();
  sent_bytes_ += sent.bytes;
  sent_.emplace(transfer_id, std::move(sent));
  while (!sent_.empty() && (sent_bytes_ > options_.keep_bytes ||
                            sent_.begin()->second.at + options_.keep < Clock::now())) {
    sent_bytes_ -= sent_.begin()->second.bytes;
    sent_.erase(sent_.begin());
  }
}

void PartTransport::resend(const part_nack_t& nack) {
  const std::lock_guard<std::mutex> lock(sent_mutex_);
  const auto it = sent_.find(nack.transfer_id);
  if (it == sent_.end()) return;  // forgotten: the RPC retry sends the message again
  for (const std::int32_t index : nack.missing) {
    if (index < 0 || static_cast<std::size_t>(index) >= it->second.parts.size()) continue;
    const auto& bytes = it->second.parts[static_cast<std::size_t>(index)];
    lcm_.publish(it->second.channel, bytes.data(), static_cast<unsigned>(bytes.size()));
    ++resent_parts_;
  }
}

void PartTransport::subscribe(const std::string& channel, Deliver deliver) {
  routes_.push_back(Route{this, std::move(deliver), nullptr});
  Route& route = routes_.back();
  route.subscription = lcm_subscribe(lcm_.getUnderlyingLCM(), (channel + kPartSuffix).c_str(),
                                     &PartTransport::onPart, &route);
  lcm_subscription_set_queue_capacity(route.subscription, kPartQueue);
}

void PartTransport::onPart(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* route) {
  auto* r = static_cast<Route*>(route);
  const auto part = safeDecode<part_t>(rbuf->data, static_cast<int>(rbuf->data_size));
  if (!part) return;
  if (const auto whole = r->self->assembler_.add(*part, Clock::now()))
    r->deliver(whole->data(), whole->size());
}

void PartTransport::onNack(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
  const auto nack = safeDecode<part_nack_t>(rbuf->data, static_cast<int>(rbuf->data_size));
  if (nack) static_cast<PartTransport*>(self)->resend(*nack);
}

void PartTransport::poll() {
  for (const auto& stalled : assembler_.stalled(Clock::now())) {
    const auto bytes = encoded(stalled.nack);
    lcm_.publish(kNackPrefix + stalled.sender, bytes.data(), static_cast<unsigned>(bytes.size()));
  }
}

}  // namespace socc::rpc
