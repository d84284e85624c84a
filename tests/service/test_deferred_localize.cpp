// LOCALIZE through the real router on memq://: the search runs on the router's search thread and
// its reply goes out from poll() (docs/relocalization.md, "Threading"); other requests are
// answered meanwhile; the answer equals the synchronous one; the queue is bounded; a retry is
// searched once; a search whose grid was replaced meanwhile is asked again; a router stopped
// during a search stops at once.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "service/request_gate.hpp"
#include "service/request_router.hpp"
#include "service_test_helpers.hpp"
#include "sim_street.hpp"
#include "socc/rpc/resend_rule.hpp"

namespace socc::service {
namespace {

using namespace std::chrono_literals;

using test::searchConfig;
using test::simulatedPoints;

localize_request_t localizeRequest(const std::vector<Eigen::Vector3f>& points,
                                   const std::string& client, std::int64_t id) {
  localize_request_t request = rpc::makeLocalizeRequest(points, 4);
  request.header.client_id = client;
  request.header.request_id = id;
  request.header.reply_channel = channels::reply(channels::kLocalize, client);
  return request;
}

// The real router on memq:// over a service whose map holds frames 0-9 of the street at their
// true poses; keeps every reply by channel.
class Harness {
 public:
  explicit Harness(int max_waiting = 2) : service(searchConfig(max_waiting)) {
    for (int k = 0; k < 10; ++k)
      EXPECT_EQ(service.integrate(test::streetIntegrate(scene, k)).header.status,
                +reply_header_t::OK);
    router.emplace(lcm, service, gate, false);
    lcm_subscribe(lcm.getUnderlyingLCM(), "SOCC/.*/REP/.*", &Harness::onReply, this);
  }

  template <typename Request>
  void send(std::string_view service_name, const Request& request) {
    const auto bytes = test::encode(request);
    lcm.publish(channels::request(service_name), bytes.data(), static_cast<unsigned>(bytes.size()));
    handle();
  }
  void handle() {
    while (lcm.handleTimeout(0) > 0) {
    }
  }
  /// Polls the router until n LOCALIZE replies arrived for client (at most 60 s).
  std::vector<localize_reply_t> awaitLocalize(const std::string& client, std::size_t n = 1) {
    const auto until = std::chrono::steady_clock::now() + 60s;
    while (localizeReplies(client).size() < n && std::chrono::steady_clock::now() < until) {
      router->poll();
      handle();
      std::this_thread::sleep_for(2ms);
    }
    return localizeReplies(client);
  }
  std::vector<localize_reply_t> localizeReplies(const std::string& client) {
    handle();
    std::vector<localize_reply_t> out;
    for (const auto& bytes : replies[channels::reply(channels::kLocalize, client)]) {
      localize_reply_t reply;
      EXPECT_GE(reply.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
      out.push_back(reply);
    }
    return out;
  }

  sim::Scene scene = test::street();
  lcm::LCM lcm{"memq://"};
  MapService service;
  AllowAllGate gate;
  std::optional<RequestRouter> router;
  std::map<std::string, std::vector<std::vector<std::uint8_t>>> replies;

 private:
  static void onReply(const lcm_recv_buf_t* rbuf, const char* channel, void* self) {
    const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
    static_cast<Harness*>(self)->replies[channel].emplace_back(data, data + rbuf->data_size);
  }
};

TEST(DeferredLocalize, ReplyComesFromPollOthersAreServedMeanwhileSameAnswerAsInline) {
  Harness h;
  const localize_request_t request = localizeRequest(simulatedPoints(h.scene, 5), "searcher", 1);
  const auto sent = std::chrono::steady_clock::now();
  h.send(channels::kLocalize, request);  // the LCM thread's part: checks, map keypoints
  const auto begun = std::chrono::steady_clock::now();
  EXPECT_TRUE(h.localizeReplies("searcher").empty()) << "the search is not answered inline";
  EXPECT_EQ(h.router->searchesUnderWay(), 1u);

  // Another robot's chunk query is answered while the search is under way (its continuation
  // only runs in poll(), so this holds however fast the search thread is).
  chunk_request_t chunk = test::everything();
  chunk.header.client_id = "tracker";
  chunk.header.reply_channel = channels::reply(channels::kGetChunk, "tracker");
  h.send(channels::kGetChunk, chunk);
  EXPECT_EQ(h.replies[chunk.header.reply_channel].size(), 1u);
  EXPECT_TRUE(h.localizeReplies("searcher").empty());

  const std::vector<localize_reply_t> replies = h.awaitLocalize("searcher");
  ASSERT_EQ(replies.size(), 1u);
  const localize_reply_t& reply = replies.front();
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  std::printf(
      "LOCALIZE: %.3f s on the LCM thread before the search (map keypoints oriented), "
      "reply after %.3f s\n",
      std::chrono::duration<double>(begun - sent).count(), reply.seconds);
  EXPECT_EQ(reply.header.request_id, 1);
  EXPECT_EQ(reply.map_epoch, h.service.map().epoch());  // the frame of the candidates
  EXPECT_EQ(h.router->searchesUnderWay(), 0u);
  ASSERT_GT(reply.num_candidates, 0);
  const Eigen::Isometry3d truth = h.scene.trajectory.poseAt(0.5);
  EXPECT_LT((fromLcm(reply.pose[0]).translation() - truth.translation()).norm(), 1.0);

  // The same candidates as the handler run inline: the search does not depend on its thread.
  const localize_reply_t inline_reply = h.service.localize(request);
  ASSERT_EQ(inline_reply.num_candidates, reply.num_candidates);
  for (std::size_t i = 0; i < reply.pose.size(); ++i) {
    EXPECT_TRUE(fromLcm(reply.pose[i]).isApprox(fromLcm(inline_reply.pose[i]), 1e-12));
    EXPECT_EQ(reply.inliers[i], inline_reply.inliers[i]);
  }
}

TEST(DeferredLocalize, ASearchWhoseGridWasReplacedMeanwhileIsAskedAgain) {
  Harness h;
  const localize_request_t request = localizeRequest(simulatedPoints(h.scene, 5), "searcher", 3);
  std::variant<localize_reply_t, MapService::PendingLocalize> begun =
      h.service.beginLocalize(request);
  auto* pending = std::get_if<MapService::PendingLocalize>(&begun);
  ASSERT_NE(pending, nullptr);
  pending->run();
  // Another grid while the search ran (as a map correction's swap): its hypotheses are in the
  // old grid's frame.
  map_command_request_t clear{};
  clear.command = map_command_request_t::CLEAR;
  ASSERT_EQ(h.service.command(clear).header.status, +reply_header_t::OK);
  const localize_reply_t reply = h.service.finishLocalize(std::move(*pending));
  EXPECT_EQ(reply.header.status, +reply_header_t::RESOURCE_EXHAUSTED) << reply.header.message;
  EXPECT_EQ(reply.num_candidates, 0);
  // MapClient sends it again (and it is searched in the new grid).
  EXPECT_EQ(rpc::matchingRule(reply.header.status, reply.header.message,
                              {rpc::searchesBusyRule(std::chrono::milliseconds(1000))}),
            0);
}

TEST(DeferredLocalize, ARetryOfASearchUnderWayIsAnsweredOnce) {
  Harness h;
  const localize_request_t request = localizeRequest(simulatedPoints(h.scene, 3), "searcher", 7);
  h.send(channels::kLocalize, request);
  h.send(channels::kLocalize, request);  // the client's retry: same request id
  EXPECT_EQ(h.router->searchesUnderWay(), 1u);
  EXPECT_EQ(h.awaitLocalize("searcher").size(), 1u);
  std::this_thread::sleep_for(50ms);
  h.router->poll();
  EXPECT_EQ(h.localizeReplies("searcher").size(), 1u);
}

TEST(DeferredLocalize, BeyondTheQueueASearchIsRefusedAtOnceAChecksIsNot) {
  Harness h(0);  // one search under way, none waiting
  const std::vector<Eigen::Vector3f> points = simulatedPoints(h.scene, 4);
  h.send(channels::kLocalize, localizeRequest(points, "first", 1));
  h.send(channels::kLocalize, localizeRequest(points, "second", 1));
  const std::vector<localize_reply_t> refused = h.localizeReplies("second");
  ASSERT_EQ(refused.size(), 1u) << "refused at once";
  EXPECT_EQ(refused[0].header.status, +reply_header_t::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused[0].header.message.find("max_waiting_searches"), std::string::npos)
      << refused[0].header.message;

  // Check mode needs no search: answered at once even now.
  localize_request_t check = localizeRequest(points, "checker", 1);
  check.check_pose.push_back(toLcm(h.scene.trajectory.poseAt(0.4)));
  check.num_check = 1;
  h.send(channels::kLocalize, check);
  const std::vector<localize_reply_t> checked = h.localizeReplies("checker");
  ASSERT_EQ(checked.size(), 1u);
  EXPECT_EQ(checked[0].header.status, +reply_header_t::OK);
  EXPECT_EQ(checked[0].num_checked, 1);

  const std::vector<localize_reply_t> first = h.awaitLocalize("first");
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].header.status, +reply_header_t::OK);
  h.send(channels::kLocalize, localizeRequest(points, "second", 2));  // room again
  EXPECT_EQ(h.router->searchesUnderWay(), 1u);
}

TEST(DeferredLocalize, StoppingDuringASearchIsQuickAndSendsNothing) {
  Harness h;
  h.service.localize(localizeRequest(simulatedPoints(h.scene, 2), "warm", 1));  // descriptors
  const auto points = simulatedPoints(h.scene, 6);
  h.send(channels::kLocalize, localizeRequest(points, "searcher", 1));
  const auto start = std::chrono::steady_clock::now();
  h.router.reset();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("router stopped %.3f s after a search started\n", seconds);
  EXPECT_LT(seconds, 10.0);
  EXPECT_TRUE(h.localizeReplies("searcher").empty());
}

}  // namespace
}  // namespace socc::service
