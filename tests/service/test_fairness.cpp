// Fairness between robots (limits.robot_integrate_rate / robot_chunk_rate): a robot beyond its
// request budget gets RESOURCE_EXHAUSTED, before any work, while the others are served.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <vector>

#include "service/request_gate.hpp"
#include "service/request_router.hpp"
#include "service/robot_rate_limiter.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

using test::scan;
using Clock = RobotRateLimiter::Clock;
constexpr std::int8_t kFairOk = reply_header_t::OK;
constexpr std::int8_t kFairExhausted = reply_header_t::RESOURCE_EXHAUSTED;

TEST(RobotRateLimiter, BurstThenRate) {
  RobotRateLimiter limiter(10.0, 5.0);
  const auto t0 = Clock::now();
  EXPECT_TRUE(limiter.admit("b", t0)) << "b active: a's limit bites";
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(limiter.admit("a", t0)) << i;
  EXPECT_FALSE(limiter.admit("a", t0)) << "burst spent";
  EXPECT_TRUE(limiter.admit("b", t0)) << "another robot has its own budget";
  EXPECT_TRUE(limiter.admit("a", t0 + std::chrono::milliseconds(100))) << "refilled at 10/s";
  EXPECT_FALSE(limiter.admit("a", t0 + std::chrono::milliseconds(150)));
}

// A robot alone (replaying a recording as fast as possible) is never held back: the limits are
// for sharing the server, and there is nobody to share with.
TEST(RobotRateLimiter, LimitsBiteUnderContentionOnly) {
  RobotRateLimiter limiter(10.0, 5.0);
  const auto t0 = Clock::now();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(limiter.admit("a", t0 + std::chrono::milliseconds(i))) << i;
  EXPECT_TRUE(limiter.admit("b", t0 + std::chrono::milliseconds(100)));
  int admitted = 0;  // b is active now: a gets at most what its budget refilled
  for (int i = 0; i < 5; ++i) admitted += limiter.admit("a", t0 + std::chrono::milliseconds(101));
  EXPECT_LE(admitted, 1);
  // b idle for more than a second: a is alone again.
  EXPECT_TRUE(limiter.admit("a", t0 + std::chrono::milliseconds(1200)));
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(limiter.admit("a", t0 + std::chrono::milliseconds(1201))) << i;
}

TEST(RobotRateLimiter, ZeroRateMeansNoLimit) {
  RobotRateLimiter limiter(0.0, 0.0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(limiter.admit("a", Clock::now()));
}

TEST(RobotRateLimiter, ForgetsIdleClientsBeyondItsCapacity) {
  RobotRateLimiter limiter(10.0, 2.0, 2);
  const auto t0 = Clock::now();
  EXPECT_TRUE(limiter.admit("a", t0));
  EXPECT_TRUE(limiter.admit("b", t0));
  // a and b refill within 0.2 s: a third client then fits without anyone losing budget.
  EXPECT_TRUE(limiter.admit("c", t0 + std::chrono::seconds(1)));
  EXPECT_TRUE(limiter.admit("a", t0 + std::chrono::seconds(1)));
}

// The real router on memq:// with low per-robot rates; counts each robot's reply statuses.
class FairnessHarness {
 public:
  FairnessHarness() : service(config()), router(lcm, service, gate, false) {
    lcm_subscribe(lcm.getUnderlyingLCM(), "SOCC/INTEGRATE/REP/.*", &FairnessHarness::onReply, this);
  }
  static ServerConfig config() {
    ServerConfig c = test::smallConfig();
    c.limits.robot_integrate_rate = 5.0;
    return c;
  }
  void send(const integrate_request_t& request) {
    const auto bytes = test::encode(request);
    lcm.publish(channels::request(channels::kIntegrate), bytes.data(),
                static_cast<unsigned>(bytes.size()));
    while (lcm.handleTimeout(0) > 0) {
    }
  }

  lcm::LCM lcm{"memq://"};
  MapService service;
  AllowAllGate gate;
  RequestRouter router;
  std::vector<reply_header_t> replies;

 private:
  static void onReply(const lcm_recv_buf_t* rbuf, const char*, void* self) {
    reply_header_t header;
    if (header._decodeNoHash(rbuf->data, 8, static_cast<int>(rbuf->data_size) - 8) >= 0)
      static_cast<FairnessHarness*>(self)->replies.push_back(header);
  }
};

TEST(Fairness, FloodingRobotIsRefusedAndTheOthersServed) {
  FairnessHarness h;
  h.send(scan("calm", 1, 3.0));
  for (int seq = 1; seq <= 20; ++seq) h.send(scan("flood", seq, 0.01 * seq));
  int ok = 0, exhausted = 0;
  std::string message;
  for (const auto& r : h.replies) {
    if (r.client_id == "calm") {
      EXPECT_EQ(r.status, kFairOk) << r.message;
      continue;
    }
    ok += r.status == kFairOk;
    if (r.status == kFairExhausted) {
      ++exhausted;
      message = r.message;
    }
  }
  EXPECT_EQ(ok, 5) << "the burst: one second's worth";
  EXPECT_EQ(exhausted, 15);
  EXPECT_NE(message.find("limits.robot_integrate_rate"), std::string::npos) << message;
  EXPECT_EQ(h.service.robots().find("flood")->integrations, 5);
  EXPECT_EQ(h.service.robots().find("calm")->integrations, 1);
}

TEST(Fairness, RobotAloneIsServedBeyondItsRate) {
  FairnessHarness h;
  for (int seq = 1; seq <= 20; ++seq) h.send(scan("alone", seq, 0.01 * seq));
  for (const auto& r : h.replies) EXPECT_EQ(r.status, kFairOk) << r.message;
  EXPECT_EQ(h.service.robots().find("alone")->integrations, 20);
}

}  // namespace
}  // namespace socc::service
