#include "sender_selection.hpp"

#include <arpa/inet.h>

#include <iostream>
#include <optional>
#include <stdexcept>
#include <vector>

namespace socc::sensors {
namespace {

// Senders remembered for the report; a flood of spoofed addresses is counted, not listed.
constexpr std::size_t kListedSenders = 8;

class SenderSelectingDecoder final : public ScanDecoder {
 public:
  SenderSelectingDecoder(const SensorConfig& config, std::unique_ptr<ScanDecoder> inner)
      : inner_(std::move(inner)), notify_(config.notify) {
    if (!config.sensor_address.empty()) selected_ = parseSensorAddress(config.sensor_address);
    chosen_ = selected_.has_value();
  }

  void feed(const Packet& packet, std::vector<SensorScan>& out) override {
    if (chosen_ && packet.source_ipv4 == 0)
      throw std::runtime_error(
          "packets without a sender address (a bag?) cannot be selected by sensor address " +
          formatIpv4(*selected_));
    if (selected_ && packet.source_ipv4 != *selected_) {
      drop(packet);
      return;
    }
    ++received_;
    if (selected_ || packet.source_ipv4 == 0) {
      inner_->feed(packet, out);
      return;
    }
    // The first sender whose packet the decoder takes (decoded, or kept to detect the model) is
    // the sensor; packets it refuses (another device's, position packets) choose nothing.
    const DecodeStats before = inner_->stats();
    inner_->feed(packet, out);
    const DecodeStats& after = inner_->stats();
    if (after.foreign == before.foreign && after.malformed == before.malformed)
      selected_ = packet.source_ipv4;
  }

  void flush(std::vector<SensorScan>& out) override {
    if (chosen_ && received_ == 0 && !senders_.empty())
      throw std::runtime_error("no packet came from the sensor address " + formatIpv4(*selected_) +
                               " (" + listSenders() + ")");
    inner_->flush(out);
  }

  const DecodeStats& stats() const override {
    stats_ = inner_->stats();
    stats_.other_sender = dropped_;
    return stats_;
  }
  std::string model() const override { return inner_->model(); }

  std::string notes() const override {
    std::string s = inner_->notes();
    if (dropped_ == 0) return s;
    if (!s.empty()) s += "\n";
    return s + "decoded the packets of " + formatIpv4(*selected_) + " only; dropped " +
           listSenders();
  }

 private:
  struct Sender {
    std::uint32_t address = 0;
    std::uint16_t port = 0;
    std::uint64_t packets = 0;
  };

  void drop(const Packet& packet) {
    ++dropped_;
    for (Sender& s : senders_)
      if (s.address == packet.source_ipv4) {
        ++s.packets;
        return;
      }
    if (senders_.size() >= kListedSenders) return;
    senders_.push_back({packet.source_ipv4, packet.source_port, 1});
    report(senders_.back());
  }

  void report(const Sender& s) const {
    const std::string why = chosen_ ? "not the selected sensor address " + formatIpv4(*selected_)
                                    : "another sender on the port; the stream decodes " +
                                          formatIpv4(*selected_) +
                                          ", the first sender (choose with --sensor-address)";
    const std::string message = "dropping the packets of " + formatIpv4(s.address) +
                                " (UDP source port " + std::to_string(s.port) + "): " + why;
    if (notify_)
      notify_(message);
    else
      std::cerr << "socc_sensors: " << message << std::endl;
  }

  std::string listSenders() const {
    std::string s;
    std::uint64_t listed = 0;
    for (const Sender& x : senders_) {
      s += (s.empty() ? "" : ", ") + std::to_string(x.packets) + " packets from " +
           formatIpv4(x.address);
      listed += x.packets;
    }
    if (dropped_ > listed) s += ", " + std::to_string(dropped_ - listed) + " from other senders";
    return s;
  }

  std::unique_ptr<ScanDecoder> inner_;
  std::function<void(const std::string&)> notify_;
  std::optional<std::uint32_t> selected_;
  bool chosen_ = false;  // selected by configuration (not the first sender)
  std::uint64_t received_ = 0;
  std::uint64_t dropped_ = 0;
  std::vector<Sender> senders_;
  mutable DecodeStats stats_;
};

}  // namespace

std::uint32_t parseSensorAddress(const std::string& text) {
  in_addr a{};
  if (inet_pton(AF_INET, text.c_str(), &a) != 1 || a.s_addr == 0)
    throw std::runtime_error("sensor address '" + text + "' is not an IPv4 address");
  return ntohl(a.s_addr);
}

std::string formatIpv4(std::uint32_t address) {
  return std::to_string(address >> 24) + "." + std::to_string((address >> 16) & 0xFF) + "." +
         std::to_string((address >> 8) & 0xFF) + "." + std::to_string(address & 0xFF);
}

std::unique_ptr<ScanDecoder> selectSender(const SensorConfig& config,
                                          std::unique_ptr<ScanDecoder> inner) {
  return std::make_unique<SenderSelectingDecoder>(config, std::move(inner));
}

}  // namespace socc::sensors
