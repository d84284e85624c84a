// MapClient against an in-process server over UDP multicast on loopback (random port, so
// concurrent test runs never see each other).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>
#include <thread>

#include "../integration/loopback_lcm_url.hpp"
#include "service/auth_gate.hpp"
#include "service/request_router.hpp"
#include "service_test_helpers.hpp"
#include "sim_street.hpp"
#include "socc/auth/message_auth.hpp"
#include "socc/rpc/resend_rule.hpp"

namespace socc::service {
namespace {

std::string randomUrl() {
  return socc::testing::randomLoopbackLcmUrl();
}

// map_server's loop in a thread: the MapService is only touched by that thread.
class InProcessServer {
 public:
  explicit InProcessServer(const std::string& url,
                           std::unique_ptr<RequestGate> gate = std::make_unique<AllowAllGate>(),
                           const ServerConfig& config = test::smallConfig())
      : lcm_(url),
        service_(config),
        gate_(std::move(gate)),
        router_(lcm_, service_, *gate_, false) {
    thread_ = std::thread([this] {
      while (!stop_) {
        lcm_.handleTimeout(20);
        router_.poll();  // replies of finished LOCALIZE searches
      }
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
  std::unique_ptr<RequestGate> gate_;
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

TEST(MapClient, LanUrlNeedsAKey) {
  rpc::ClientOptions options;
  options.lcm_url = "udpm://239.1.2.3:7667?ttl=1";
  try {
    rpc::MapClient client{options};
    ADD_FAILURE() << "ttl=1 without a key was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("needs an HMAC key"), std::string::npos) << e.what();
  }
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
  EXPECT_FALSE(client.answered());  // a server that never answered: perhaps not running
}

TEST(MapClient, RequestWithInconsistentArraysIsNotSent) {
  // encode() would read past the short row; the client refuses before encoding or signing.
  rpc::ClientOptions options = clientOptions(randomUrl(), "robot1");
  options.timeout = std::chrono::milliseconds(50);
  rpc::MapClient client(options);
  auto request = test::scan("robot1", 1);
  request.xyz[1].pop_back();
  const auto result = client.integrate(request);
  EXPECT_FALSE(result.ok());
  EXPECT_FALSE(result.error.timed_out);
  EXPECT_EQ(result.error.status, +reply_header_t::INVALID_ARGUMENT);
  EXPECT_EQ(result.attempts, 0);
  request = test::scan("robot1", 1);
  request.time.resize(3);  // num_times is 0
  EXPECT_EQ(client.integrate(request).error.status, +reply_header_t::INVALID_ARGUMENT);
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
  EXPECT_GT(chunk.bytes_received, chunk.reply->num_voxels * 14);  // 14 bytes of features a voxel

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

TEST(MapClient, GetKeyframesOverUdp) {
  const std::string url = randomUrl();
  ServerConfig config = test::smallConfig();
  config.consistency.enabled = true;
  config.consistency.keyframe_distance = 3.0;
  InProcessServer server(url, std::make_unique<AllowAllGate>(), config);
  ASSERT_TRUE(server.good()) << "cannot open " << url;
  rpc::MapClient client(clientOptions(url, "robot1"));
  for (int seq = 1; seq <= 7; ++seq)  // one metre apart: keyframes at seq 1, 4, 7
    ASSERT_TRUE(client.integrate(test::scan("robot1", seq, seq - 1.0)).ok());
  rpc::Result<keyframes_reply_t> reply;
  for (int i = 0; i < 100; ++i) {  // the service's worker places them into its graph
    reply = client.getKeyframes("robot1");
    if (reply.ok() && reply.reply->keyframes.num_poses == 3) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(reply.ok()) << reply.error.message;
  const pose_history_t& k = reply.reply->keyframes;
  ASSERT_EQ(k.num_poses, 3);
  EXPECT_EQ(k.seq, (std::vector<std::int64_t>{1, 4, 7}));
  EXPECT_NEAR(k.translation[0][2], 6.0, 1e-9);  // no closure: where it was integrated
  EXPECT_NEAR(k.quaternion[0][2], 1.0, 1e-9);
  EXPECT_FALSE(reply.reply->truncated);
  // Paging: from seq 2, one at a time.
  const auto page = client.getKeyframes("robot1", 2, 1);
  ASSERT_TRUE(page.ok());
  EXPECT_EQ(page.reply->keyframes.seq, (std::vector<std::int64_t>{4}));
  EXPECT_TRUE(page.reply->truncated);
  const auto ghost = client.getKeyframes("ghost");
  EXPECT_FALSE(ghost.error.timed_out);
  EXPECT_EQ(ghost.error.status, +reply_header_t::NOT_FOUND);
}

TEST(MapClient, GetKeyframesWithoutTheConsistencyServiceIsRefused) {
  const std::string url = randomUrl();
  InProcessServer server(url);
  ASSERT_TRUE(server.good()) << "cannot open " << url;
  rpc::MapClient client(clientOptions(url, "robot1"));
  ASSERT_TRUE(client.integrate(test::scan("robot1", 1)).ok());
  const auto reply = client.getKeyframes("robot1");
  EXPECT_FALSE(reply.error.timed_out);
  EXPECT_EQ(reply.error.status, +reply_header_t::FAILED_PRECONDITION);
  EXPECT_NE(reply.error.message.find("--consistency"), std::string::npos) << reply.error.message;
}

TEST(MapClient, ReportTrackingOverUdp) {
  const std::string url = randomUrl();
  InProcessServer server(url);
  ASSERT_TRUE(server.good());
  rpc::MapClient client(clientOptions(url, "robot1"));
  EXPECT_FALSE(client.answered());
  const auto early = client.reportTracking(robot_status_request_t::LOST, "no frames", 0, 0);
  EXPECT_EQ(early.error.status, +reply_header_t::NOT_FOUND);
  EXPECT_TRUE(client.answered());  // a refusal is an answer too

  ASSERT_TRUE(client.integrate(test::scan("robot1", 1)).ok());
  const auto lost = client.reportTracking(robot_status_request_t::LOST, "diverged", 1, 100000);
  ASSERT_TRUE(lost.ok()) << lost.error.message;
  EXPECT_EQ(lost.reply->state.tracking_state, +robot_status_request_t::LOST);
  const auto refused = client.integrate(test::scan("robot1", 2));
  EXPECT_FALSE(refused.ok());
  EXPECT_EQ(rpc::statusName(refused.error.status), "FAILED_PRECONDITION");
  EXPECT_EQ(refused.error.message,
            "robot robot1 reported LOST at seq 1 (diverged); INTEGRATE refused until it reports "
            "TRACKING");
  ASSERT_TRUE(client.reportTracking(robot_status_request_t::TRACKING, "", 2, 200000).ok());
  EXPECT_TRUE(client.integrate(test::scan("robot1", 2)).ok());
  const auto stats = client.getStats();
  ASSERT_TRUE(stats.ok());
  ASSERT_EQ(stats.reply->stats.robots.size(), 1u);
  EXPECT_EQ(stats.reply->stats.robots[0].tracking_state, +robot_status_request_t::TRACKING);
  EXPECT_EQ(stats.reply->stats.robots[0].refused_integrations, 1);
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

// Signing ----------------------------------------------------------------------------------

constexpr std::uint8_t kKeyByte = 0x3c;

// A 0600 key file (hex) of 32 kKeyByte bytes in dir.
std::string writeKeyFile(const test::TempDir& dir) {
  const auto file = dir.path() / "map.key";
  {
    std::ofstream out(file);
    for (int i = 0; i < 32; ++i) out << "3c";  // hex of kKeyByte
  }
  ::chmod(file.c_str(), 0600);
  return file.string();
}

auth::SharedKey mapClientKey() {
  return auth::SharedKey::fromBytes(std::vector<std::uint8_t>(32, kKeyByte));
}

TEST(MapClientAuth, SignedClientIsServedUnsignedIsRefused) {
  const std::string url = randomUrl();
  test::TempDir dir;
  InProcessServer server(url, std::make_unique<AuthGate>(mapClientKey(), false));
  ASSERT_TRUE(server.good());
  rpc::ClientOptions options = clientOptions(url, "robot1");
  options.key_file = writeKeyFile(dir);
  rpc::MapClient client(options);
  const auto applied = client.integrate(test::scan("robot1", 1));
  ASSERT_TRUE(applied.ok()) << applied.error.message;
  EXPECT_FALSE(applied.reply->duplicate);

  rpc::MapClient anonymous(clientOptions(url, "robot2"));
  const auto refused = anonymous.integrate(test::scan("robot2", 1));
  ASSERT_FALSE(refused.ok());
  EXPECT_FALSE(refused.error.timed_out);
  EXPECT_EQ(refused.error.status, +reply_header_t::UNAUTHENTICATED);
  const auto stats = anonymous.getStats();  // queries stay open without --auth-queries
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats.reply->stats.integrations, 1);
  EXPECT_EQ(stats.reply->stats.auth_failures, 1);
}

TEST(MapClientAuth, KeyFileReadableByOthersIsRefused) {
  test::TempDir dir;
  rpc::ClientOptions options = clientOptions("memq://", "robot1");
  options.key_file = writeKeyFile(dir);
  ::chmod(options.key_file.c_str(), 0644);
  EXPECT_THROW(rpc::MapClient{options}, std::runtime_error);
}

// Every attempt as published, seen by a raw listener standing in for an unresponsive server.
class AttemptRecorder {
 public:
  explicit AttemptRecorder(const std::string& url) : lcm_(url) {
    lcm_subscribe(lcm_.getUnderlyingLCM(), channels::request(channels::kIntegrate).c_str(),
                  &AttemptRecorder::onRequest, this);
    thread_ = std::thread([this] {
      while (!stop_) lcm_.handleTimeout(10);
    });
  }
  ~AttemptRecorder() {
    stop_ = true;
    thread_.join();
  }
  std::vector<std::vector<std::uint8_t>> attempts() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return attempts_;
  }

 private:
  static void onRequest(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
    auto* recorder = static_cast<AttemptRecorder*>(self);
    const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
    const std::lock_guard<std::mutex> lock(recorder->mutex_);
    recorder->attempts_.emplace_back(data, data + rbuf->data_size);
  }

  lcm::LCM lcm_;
  std::mutex mutex_;
  std::vector<std::vector<std::uint8_t>> attempts_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(MapClientAuth, EveryRetryIsResignedWithANewCounter) {
  const std::string url = randomUrl();
  test::TempDir dir;
  AttemptRecorder recorder(url);
  rpc::ClientOptions options = clientOptions(url, "robot1");
  options.key_file = writeKeyFile(dir);
  options.timeout = std::chrono::milliseconds(100);
  options.max_attempts = 3;
  rpc::MapClient client(options);
  EXPECT_TRUE(client.integrate(test::scan("robot1", 7)).error.timed_out);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));

  const auto attempts = recorder.attempts();
  ASSERT_EQ(attempts.size(), 3u);
  auth::Verifier verifier(mapClientKey());  // the server's view: each attempt is fresh and genuine
  std::optional<integrate_request_t> first;
  for (const auto& bytes : attempts) {
    integrate_request_t request{};
    ASSERT_EQ(request.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
              static_cast<int>(bytes.size()));
    const auth::AuthResult result =
        verifier.verifyEncoded(request.header, bytes.data(), bytes.size());
    EXPECT_TRUE(result.ok) << result.reason;
    if (!first) first = request;
    EXPECT_EQ(request.header.request_id, first->header.request_id);
    EXPECT_EQ(request.seq, 7);
  }
  EXPECT_FALSE(verifier.verifyEncoded(first->header, attempts[0].data(), attempts[0].size()).ok);
}

}  // namespace
}  // namespace socc::service

namespace socc::service {
namespace {

// A search refused because the server's searches are all taken is sent again until one is free.
TEST(MapClient, LocalizeWaitsWhileTheServersSearchesAreTaken) {
  const std::string url = randomUrl();
  InProcessServer server(url, std::make_unique<AllowAllGate>(), test::searchConfig(0));
  ASSERT_TRUE(server.good());
  const sim::Scene scene = test::street();
  rpc::MapClient mapper(clientOptions(url, "mapper"));
  for (int k = 0; k < 10; ++k) ASSERT_TRUE(mapper.integrate(test::streetIntegrate(scene, k)).ok());

  rpc::MapClient first(clientOptions(url, "first")), second(clientOptions(url, "second"));
  rpc::Result<localize_reply_t> first_reply;
  std::thread searching([&] {
    first_reply = first.localize(rpc::makeLocalizeRequest(test::simulatedPoints(scene, 5), 4));
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // first's search under way
  const rpc::Result<localize_reply_t> second_reply =
      second.localize(rpc::makeLocalizeRequest(test::simulatedPoints(scene, 6), 4));
  searching.join();
  EXPECT_TRUE(first_reply.ok()) << first_reply.error.message;
  EXPECT_TRUE(second_reply.ok()) << second_reply.error.message;
  const rpc::Result<stats_reply_t> stats = mapper.getStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_GE(stats.reply->stats.rejected_requests, 1) << "second was never refused as busy";
}

}  // namespace
}  // namespace socc::service

namespace socc::service {
namespace {

// Which refusals MapClient sends again, and how long it pauses.
TEST(ResendRule, OnlyTheListedRefusalsAreResent) {
  const auto busy = rpc::searchesBusyRule(std::chrono::milliseconds(30000));
  const std::string rate_message = "robot r1 over 20 integrations/s: slow down";
  EXPECT_EQ(rpc::matchingRule(reply_header_t::RESOURCE_EXHAUSTED, rate_message,
                              {rpc::kRateLimitedRule, busy}),
            0);
  EXPECT_EQ(rpc::matchingRule(reply_header_t::RESOURCE_EXHAUSTED, "searches busy, try again",
                              {rpc::kRateLimitedRule, busy}),
            1);
  EXPECT_EQ(rpc::matchingRule(reply_header_t::RESOURCE_EXHAUSTED, "searches busy, try again",
                              {rpc::kRateLimitedRule}),
            -1)
      << "only LOCALIZE waits for a free search";
  EXPECT_EQ(rpc::matchingRule(reply_header_t::RESOURCE_EXHAUSTED, "request too large", {busy}), -1);
  EXPECT_EQ(
      rpc::matchingRule(reply_header_t::INVALID_ARGUMENT, rate_message, {rpc::kRateLimitedRule}),
      -1);
  EXPECT_EQ(rpc::kRateLimitedRule.pause(1), std::chrono::milliseconds(10));
  EXPECT_EQ(rpc::kRateLimitedRule.pause(30), std::chrono::milliseconds(100));
  EXPECT_EQ(busy.pause(7), std::chrono::milliseconds(250));
}

}  // namespace
}  // namespace socc::service
