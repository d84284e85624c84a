// Live scans over LCM (socc::scan_t on SOCC/SCAN/<robot_id>).
#include <deque>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "socc/channels.hpp"
#include "socc/labels.hpp"
#include "socc/lcm_url.hpp"
#include "socc/odom/scan_source.hpp"
#include "socc/scan_t.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::odom {
namespace {

// Empty when the message is self-consistent, otherwise why it is rejected.
std::string checkScan(const scan_t& m) {
  if (std::string why = wire::checkArrays(m); !why.empty()) return why;
  if (m.num_labels != 0 && m.num_labels != m.num_points)
    return "num_labels is neither 0 nor num_points";
  if (m.num_times != 0 && m.num_times != m.num_points)
    return "num_times is neither 0 nor num_points";
  for (const auto l : m.label)
    if (!isValidClass(l)) return "label " + std::to_string(l) + " is not a class id 0..19";
  return {};
}

// The network rule is checked before any socket is opened. Scans are not signed, so they are
// only read on this machine (ttl=0), also when the map service runs on a LAN (docs/fleet.md).
const std::string& checkedUrl(const std::string& url) {
  if (checkLcmUrl(url, LcmAuth::kKeyConfigured).empty() && !checkLcmUrl(url).empty())
    throw std::runtime_error(
        "scans are not signed, so they are only read from this machine: "
        "give --scan-lcm-url udpm://239.x.y.z:port?ttl=0 (not " +
        url + ")");
  if (const std::string why = checkLcmUrl(url); !why.empty())
    throw std::runtime_error("LCM URL " + url + ": " + why);
  return url;
}

class LcmScanSource final : public ScanSource {
 public:
  LcmScanSource(const std::string& url, const std::string& robot_id,
                std::chrono::milliseconds idle_timeout)
      : lcm_(checkedUrl(url)), idle_timeout_(idle_timeout) {
    if (!lcm_.good()) throw std::runtime_error("cannot open LCM at " + url);
    lcm_.subscribe(channels::scan(robot_id), &LcmScanSource::onScan, this);
  }

  std::optional<Scan> next() override {
    auto deadline = std::chrono::steady_clock::now() + idle_timeout_;
    while (queue_.empty()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      if (lcm_.handleTimeout(static_cast<int>(left.count())) < 0)
        throw std::runtime_error("LCM receive error");
    }
    Scan scan = std::move(queue_.front());
    queue_.pop_front();
    return scan;
  }

  std::size_t remaining() const override { return 0; }
  bool live() const override { return true; }

 private:
  void onScan(const lcm::ReceiveBuffer*, const std::string& channel, const scan_t* m) {
    if (const std::string why = checkScan(*m); !why.empty()) {
      std::cerr << "odom_client: skipping malformed scan on " << channel << " (seq " << m->seq
                << "): " << why << "\n";
      return;
    }
    Scan scan;
    scan.utime = m->utime;
    scan.seq = m->seq;
    scan.name = channel + "#" + std::to_string(m->seq);
    scan.cloud.points = wire::pointsFromRows(m->xyz);
    scan.cloud.labels.assign(m->label.begin(), m->label.end());
    scan.cloud.times = m->time;
    queue_.push_back(std::move(scan));
  }

  lcm::LCM lcm_;
  std::chrono::milliseconds idle_timeout_;
  std::deque<Scan> queue_;
};

}  // namespace

std::unique_ptr<ScanSource> openLcmScans(const std::string& lcm_url, const std::string& robot_id,
                                         std::chrono::milliseconds idle_timeout) {
  return std::make_unique<LcmScanSource>(lcm_url, robot_id, idle_timeout);
}

}  // namespace socc::odom
