// MapClient against an in-process server over UDP multicast on loopback (random port, so
// concurrent test runs never see each other).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "service/request_router.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

std::string randomUrl() {
  std::random_device rd;
  std::mt19937 rng(rd() ^ static_cast<unsigned>(::getpid()));
  return "udpm://239.255." + std::to_string(rng() % 250 + 1) + "." +
         std::to_string(rng() % 250 + 1) + ":" + std::to_string(30000 + rng() % 10000) +
         "?ttl=0&recv_buf_size=67108864";
}

// map_server's loop in a thread: the MapService is only touched by that thread.
class InProcessServer {
 public:
  explicit InProcessServer(const std::string& url)
      : lcm_(url), service_(test::smallConfig()), router_(lcm_, service_, gate_, false) {
    thread_ = std::thread([this] {
      while (!stop_) lcm_.handleTimeout(20);
    });
  }
  ~InProcessServer() {
    stop_ = true;
    thread_.join();
  }
  bool good() { return lcm_.good(); }

 private:
  lcm::LCM lcm_;
  MapService service_;
  AllowAllGate gate_;
  RequestRouter router_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

rpc::ClientOptions clientOptions(const std::string& url, const std::string& id) {
  rpc::ClientOptions options;
  options.lcm_url = url;
  options.client_id = id;
  options.timeout = std::chrono::milliseconds(1000);
  options.max_attempts = 3;
  return options;
}

TEST(MapClient, RejectsBadUrlAndClientId) {
  rpc::ClientOptions options;
  options.lcm_url = "udpm://239.1.2.3:7667?ttl=1";
  EXPECT_THROW(rpc::MapClient{options}, std::runtime_error);
  options.lcm_url = "memq://";
  options.client_id = "a/b";
  EXPECT_THROW(rpc::MapClient{options}, std::runtime_error);
}

TEST(MapClient, TimesOutWithoutServer) {
  rpc::ClientOptions options = clientOptions(randomUrl(), "lonely");
  options.timeout = std::chrono::milliseconds(50);
  options.max_attempts = 2;
  rpc::MapClient client(options);
  const auto result = client.getStats();
  EXPECT_FALSE(result.ok());
  EXPECT_TRUE(result.error.timed_out);
  EXPECT_EQ(result.attempts, 2);
}

TEST(MapClient, AllServicesOverUdp) {
  const std::string url = randomUrl();
  InProcessServer server(url);
  ASSERT_TRUE(server.good())
      << "cannot open " << url
      << ": is multicast routed to lo? (ip route replace 224.0.0.0/4 dev lo)";
  rpc::MapClient client(clientOptions(url, "robot1"));

  auto request = test::scan("robot1", 1);
  const auto first = client.integrate(request);
  ASSERT_TRUE(first.ok()) << first.error.message;
  EXPECT_FALSE(first.reply->duplicate);
  EXPECT_EQ(first.reply->header.client_id, "robot1");
  const auto retry = client.integrate(request);  // same seq again: acknowledged, not applied
  ASSERT_TRUE(retry.ok());
  EXPECT_TRUE(retry.reply->duplicate);
  EXPECT_EQ(retry.reply->map_version, first.reply->map_version);

  const auto chunk = client.getChunk(rpc::sphereChunkRequest(Eigen::Vector3d::Zero(), 20.0));
  ASSERT_TRUE(chunk.ok()) << chunk.error.message;
  EXPECT_GT(chunk.reply->num_voxels, 0);
  EXPECT_GT(chunk.bytes_received, chunk.reply->num_voxels * 20);

  const auto stats = client.getStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats.reply->stats.integrations, 1);
  ASSERT_EQ(stats.reply->stats.num_robots, 1);

  const auto pose = client.getRobotPose("robot1");
  ASSERT_TRUE(pose.ok());
  EXPECT_EQ(pose.reply->state.last_seq, 1);
  const auto unknown = client.getRobotPose("ghost");
  EXPECT_FALSE(unknown.ok());
  EXPECT_FALSE(unknown.error.timed_out);
  EXPECT_EQ(unknown.error.status, +reply_header_t::NOT_FOUND);

  render_request_t render{};
  for (int i = 0; i < 3; ++i) {
    render.box_min[i] = -5.0;
    render.box_max[i] = 5.0;
  }
  const auto image = client.render(render);
  ASSERT_TRUE(image.ok()) << image.error.message;
  EXPECT_EQ(image.reply->width, 20);
}

TEST(MapClient, OneThreadIntegratesWhileAnotherFetches) {
  const std::string url = randomUrl();
  InProcessServer server(url);
  ASSERT_TRUE(server.good());
  rpc::MapClient client(clientOptions(url, "robot1"));
  std::atomic<int> failures{0};
  std::thread integrator([&] {
    for (int seq = 1; seq <= 8; ++seq)
      if (!client.integrate(test::scan("robot1", seq, 0.2 * seq)).ok()) ++failures;
  });
  for (int i = 0; i < 8; ++i)
    if (!client.getChunk(rpc::sphereChunkRequest(Eigen::Vector3d::Zero(), 15.0)).ok()) ++failures;
  integrator.join();
  EXPECT_EQ(failures, 0);
  const auto stats = client.getStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats.reply->stats.integrations, 8);
}

}  // namespace
}  // namespace socc::service
