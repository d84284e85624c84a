// Request authentication through the real router (in-process memq://) with an AuthGate:
// unsigned, forged and replayed requests are refused with UNAUTHENTICATED, change nothing and
// are counted; signed ones pass. Also: replay counters survive a snapshot.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <string>
#include <vector>

#include "service/auth_gate.hpp"
#include "service/request_router.hpp"
#include "service/snapshot_metadata.hpp"
#include "service_test_helpers.hpp"
#include "socc/auth/message_auth.hpp"

namespace socc::service {
namespace {

using test::scan;

auth::SharedKey testKey() {
  return auth::SharedKey::fromBytes(std::vector<std::uint8_t>(32, 0x5a));
}
auth::SharedKey otherKey() {
  return auth::SharedKey::fromBytes(std::vector<std::uint8_t>(32, 0x17));
}

// Server router with an AuthGate plus a listener on every reply channel (one memq instance).
class AuthHarness {
 public:
  explicit AuthHarness(bool auth_queries)
      : service(test::smallConfig()),
        gate(testKey(), auth_queries),
        router(lcm, service, gate, false) {
    lcm_subscribe(lcm.getUnderlyingLCM(), "SOCC/.*/REP/.*", &AuthHarness::onReply, this);
  }

  /// Sends bytes and returns the status of the reply they produce.
  std::optional<reply_header_t> send(std::string_view service_name,
                                     const std::vector<std::uint8_t>& bytes) {
    const std::size_t before = replies.size();
    lcm.publish(channels::request(service_name), bytes.data(), static_cast<unsigned>(bytes.size()));
    while (lcm.handleTimeout(0) > 0) {
    }
    if (replies.size() != before + 1) return std::nullopt;
    reply_header_t header;
    const auto& reply = replies.back();
    if (header._decodeNoHash(reply.data(), 8, static_cast<int>(reply.size()) - 8) < 0)
      return std::nullopt;
    return header;
  }

  lcm::LCM lcm{"memq://"};
  MapService service;
  AuthGate gate;
  RequestRouter router;
  std::vector<std::vector<std::uint8_t>> replies;

 private:
  static void onReply(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* self) {
    const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
    static_cast<AuthHarness*>(self)->replies.emplace_back(data, data + rbuf->data_size);
  }
};

template <typename Request>
std::vector<std::uint8_t> signedBytes(Request request, std::int64_t counter,
                                      const auth::SharedKey& key = testKey()) {
  auth::sign(request, key, counter);
  return test::encode(request);
}

stats_request_t statsRequest() {
  stats_request_t request{};
  request.header.client_id = "tester";
  request.header.reply_channel = channels::reply(channels::kGetStats, "tester");
  return request;
}

map_command_request_t clearRequest() {
  map_command_request_t request{};
  request.header.client_id = "robot1";
  request.header.reply_channel = channels::reply(channels::kMapCommand, "robot1");
  request.command = map_command_request_t::CLEAR;
  return request;
}

constexpr std::int8_t kOk = reply_header_t::OK;
constexpr std::int8_t kUnauthenticated = reply_header_t::UNAUTHENTICATED;

TEST(AuthGate, UnsignedIntegrateIsRefusedAndChangesNothing) {
  AuthHarness h(false);
  const auto reply = h.send(channels::kIntegrate, test::encode(scan("robot1", 1)));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, kUnauthenticated);
  EXPECT_NE(reply->message.find("not signed"), std::string::npos) << reply->message;
  EXPECT_EQ(h.service.map().stats().num_voxels, 0);
  EXPECT_EQ(h.service.robots().size(), 0u);
  EXPECT_EQ(h.router.counters().auth_failures, 1);
}

TEST(AuthGate, ForgedMacIsRefused) {
  AuthHarness h(false);
  // Signed with the wrong key, and a correctly signed request modified afterwards.
  EXPECT_EQ(h.send(channels::kIntegrate, signedBytes(scan("robot1", 1), 10, otherKey()))->status,
            kUnauthenticated);
  integrate_request_t tampered = scan("robot1", 1);
  auth::sign(tampered, testKey(), 11);
  tampered.sensor_pose.translation[0] += 1.0;
  const auto reply = h.send(channels::kIntegrate, test::encode(tampered));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, kUnauthenticated);
  EXPECT_NE(reply->message.find("mac does not match"), std::string::npos) << reply->message;
  EXPECT_EQ(h.service.map().stats().num_voxels, 0);
  EXPECT_EQ(h.router.counters().auth_failures, 2);
}

TEST(AuthGate, SignedIntegrateIsAppliedAndItsReplayRefused) {
  AuthHarness h(false);
  const auto bytes = signedBytes(scan("robot1", 1), 100);
  EXPECT_EQ(h.send(channels::kIntegrate, bytes)->status, kOk);
  const std::int64_t voxels = h.service.map().stats().num_voxels;
  const std::int64_t version = h.service.map().version();
  EXPECT_GT(voxels, 0);

  const auto replay = h.send(channels::kIntegrate, bytes);
  ASSERT_TRUE(replay);
  EXPECT_EQ(replay->status, kUnauthenticated);
  EXPECT_NE(replay->message.find("replay"), std::string::npos) << replay->message;
  // An older counter (a captured earlier request) is refused too.
  EXPECT_EQ(h.send(channels::kIntegrate, signedBytes(scan("robot1", 2), 99))->status,
            kUnauthenticated);
  EXPECT_EQ(h.service.map().version(), version);
  EXPECT_EQ(h.service.integrations(), 1);
  EXPECT_EQ(h.router.counters().auth_failures, 2);

  // A retry re-signed with a new counter is accepted and deduplicated on (client, seq).
  EXPECT_EQ(h.send(channels::kIntegrate, signedBytes(scan("robot1", 1), 101))->status, kOk);
  EXPECT_EQ(h.service.integrations(), 1);
}

TEST(AuthGate, MapCommandNeedsSignature) {
  AuthHarness h(false);
  ASSERT_EQ(h.send(channels::kIntegrate, signedBytes(scan("robot1", 1), 1))->status, kOk);
  const std::int64_t voxels = h.service.map().stats().num_voxels;
  EXPECT_EQ(h.send(channels::kMapCommand, test::encode(clearRequest()))->status, kUnauthenticated);
  EXPECT_EQ(h.service.map().stats().num_voxels, voxels);
  EXPECT_EQ(h.send(channels::kMapCommand, signedBytes(clearRequest(), 2))->status, kOk);
  EXPECT_EQ(h.service.map().stats().num_voxels, 0);
}

TEST(AuthGate, TrackingReportNeedsSignature) {
  // A report changes state (LOST stops the robot's integrations), so it is signed like one.
  AuthHarness h(false);
  ASSERT_EQ(h.send(channels::kIntegrate, signedBytes(scan("robot1", 1), 1))->status, kOk);
  const auto lost = test::trackingReport("robot1", robot_status_request_t::LOST, 1);
  EXPECT_EQ(h.send(channels::kRobotStatus, test::encode(lost))->status, kUnauthenticated);
  EXPECT_EQ(h.service.robots().find("robot1")->tracking_state, +robot_status_request_t::TRACKING);
  EXPECT_EQ(h.send(channels::kRobotStatus, signedBytes(lost, 2))->status, kOk);
  EXPECT_EQ(h.service.robots().find("robot1")->tracking_state, +robot_status_request_t::LOST);
}

TEST(AuthGate, QueriesAreOpenUnlessAuthQueries) {
  AuthHarness open(false);
  EXPECT_EQ(open.send(channels::kGetStats, test::encode(statsRequest()))->status, kOk);

  AuthHarness closed(true);
  const auto reply = closed.send(channels::kGetStats, test::encode(statsRequest()));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, kUnauthenticated);
  EXPECT_EQ(closed.send(channels::kGetStats, signedBytes(statsRequest(), 5))->status, kOk);
  EXPECT_EQ(closed.router.counters().auth_failures, 1);
}

TEST(AuthGate, FailuresAreReportedInStats) {
  AuthHarness h(false);
  h.send(channels::kIntegrate, test::encode(scan("robot1", 1)));
  h.send(channels::kMapCommand, test::encode(clearRequest()));
  ASSERT_EQ(h.send(channels::kGetStats, test::encode(statsRequest()))->status, kOk);
  stats_reply_t stats;
  const auto& raw = h.replies.back();
  ASSERT_EQ(stats.decode(raw.data(), 0, static_cast<int>(raw.size())),
            static_cast<int>(raw.size()));
  EXPECT_EQ(stats.stats.auth_failures, 2);
  EXPECT_EQ(stats.stats.rejected_requests, 2);
}

TEST(AuthGate, ReplayCountersSurviveASnapshot) {
  test::TempDir dir;
  const auto file = dir.path() / "map.snap";
  const auto bytes = signedBytes(scan("robot1", 1), 500);
  {
    AuthHarness h(false);
    h.service.attachReplayGuard(h.gate.replayGuard());
    ASSERT_EQ(h.send(channels::kIntegrate, bytes)->status, kOk);
    h.service.saveSnapshot(file);
  }
  AuthHarness restored(false);
  restored.service.attachReplayGuard(restored.gate.replayGuard());
  restored.service.loadSnapshot(file);
  EXPECT_EQ(restored.gate.replayGuard().counters().at("robot1"), 500);
  EXPECT_EQ(restored.send(channels::kIntegrate, bytes)->status, kUnauthenticated);
  EXPECT_EQ(restored.send(channels::kIntegrate, signedBytes(scan("robot1", 2), 501))->status, kOk);
}

TEST(SnapshotMetadata, WithoutCountersStaysPlainLcm) {
  SnapshotMetadata metadata;
  metadata.journal_sequence = 7;
  const auto plain = decodeSnapshotMetadata(encodeSnapshotMetadata(metadata));
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->journal_sequence, 7);
  EXPECT_TRUE(plain->auth_counters.empty());

  metadata.auth_counters = {{"robot1", 42}, {"robot2", 7}};
  const auto with = decodeSnapshotMetadata(encodeSnapshotMetadata(metadata));
  ASSERT_TRUE(with);
  EXPECT_EQ(with->journal_sequence, 7);
  EXPECT_EQ(with->auth_counters, metadata.auth_counters);
}

}  // namespace
}  // namespace socc::service
