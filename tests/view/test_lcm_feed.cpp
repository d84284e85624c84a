// socc-view's LCM side over UDP multicast on loopback (ttl=0): a scan a robot sends whole, and
// one a LAN-mode robot sends as parts (PartTransport), both reach the model.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "../integration/loopback_lcm_url.hpp"
#include "lcm_feed.hpp"
#include "socc/channels.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::view {
namespace {

std::string randomUrl() { return socc::testing::randomLoopbackLcmUrl(); }

// A 2000-point scan (~30 KB encoded: 25 parts of 1200 bytes) of robot at x.
std::vector<std::uint8_t> encodedScan(const std::string& robot, double x) {
  LabeledCloud cloud;
  for (int i = 0; i < 2000; ++i) {
    cloud.points.emplace_back(0.01f * static_cast<float>(i), 5.0f, -1.0f);
    cloud.labels.push_back(40);
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = x;
  integrate_request_t request = rpc::makeIntegrateRequest(1, 100000, pose, cloud);
  request.header.client_id = robot;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(request.getEncodedSize()));
  request.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// Waits up to 5 s for robot's scan in the model; its x position, or NaN.
double scanX(const ViewModel& model, const std::string& robot) {
  for (int i = 0; i < 100; ++i) {
    const double x = model.read([&robot](const ViewModel& m) {
      const auto it = m.robots().find(robot);
      return it == m.robots().end() || it->second.scan.empty() ? std::nan("")
                                                                : it->second.translation[0];
    });
    if (!std::isnan(x)) return x;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return std::nan("");
}

TEST(LcmFeed, ScansSentWholeAndAsLanPartsBothReachTheModel) {
  const std::string url = randomUrl();
  ViewModel model;
  const LcmFeed feed(url, model);
  lcm::LCM robot_lcm(url);
  ASSERT_TRUE(robot_lcm.good());
  const std::string channel = channels::request(channels::kIntegrate);

  const auto whole = encodedScan("whole", 1.0);
  robot_lcm.publish(channel, whole.data(), static_cast<unsigned>(whole.size()));
  EXPECT_DOUBLE_EQ(scanX(model, "whole"), 1.0);

  rpc::PartOptions lan;
  lan.split = true;
  rpc::PartTransport parts(robot_lcm, "robot", lan);
  const auto split = encodedScan("lan", 2.0);
  ASSERT_GT(split.size(), 10 * lan.part_bytes);
  ASSERT_EQ(parts.publish(channel, split.data(), split.size()), 0);
  EXPECT_DOUBLE_EQ(scanX(model, "lan"), 2.0);
  EXPECT_EQ(feed.dropped(), 0);
}

}  // namespace
}  // namespace socc::view
