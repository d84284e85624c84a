// Hostile and malformed messages through the real router (in-process memq://): each gets an
// error reply or is dropped, never crashes the server, and never changes the map.
#include <gtest/gtest.h>

#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <optional>

#include "service/request_router.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

using test::scan;

struct Received {
  std::string channel;
  std::vector<std::uint8_t> bytes;
};

// Server router plus a listener on every reply channel, sharing one memq LCM instance.
class RouterHarness {
 public:
  explicit RouterHarness(const ServerConfig& config)
      : service(config), router(lcm, service, gate, false) {
    // LCM's C API: its C++ raw-handler wrapper trips UBSan's vptr check.
    lcm_subscribe(lcm.getUnderlyingLCM(), "SOCC/.*/REP/.*", &RouterHarness::onReply, this);
  }

  void send(const std::string& service_name, const std::vector<std::uint8_t>& bytes) {
    lcm.publish(channels::request(service_name), bytes.data(), static_cast<unsigned>(bytes.size()));
    while (lcm.handleTimeout(0) > 0) {
    }
  }

  lcm::LCM lcm{"memq://"};
  MapService service;
  AllowAllGate gate;
  RequestRouter router;
  std::vector<Received> replies;

 private:
  static void onReply(const lcm_recv_buf_t* rbuf, const char* channel, void* self) {
    const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
    static_cast<RouterHarness*>(self)->replies.push_back({channel, {data, data + rbuf->data_size}});
  }
};

std::optional<reply_header_t> headerOf(const Received& reply) {
  reply_header_t header;
  if (header._decodeNoHash(reply.bytes.data(), 8, static_cast<int>(reply.bytes.size()) - 8) < 0)
    return std::nullopt;
  return header;
}

// Offset of num_points in an encoded integrate_request_t.
std::size_t numPointsOffset(const integrate_request_t& request) {
  return 8 + static_cast<std::size_t>(request.header._getEncodedSizeNoHash()) + 8 + 8 + 56;
}

void putInt32(std::vector<std::uint8_t>& bytes, std::size_t offset, std::int32_t value) {
  for (int i = 0; i < 4; ++i)
    bytes[offset + i] =
        static_cast<std::uint8_t>(static_cast<std::uint32_t>(value) >> (24 - 8 * i));
}

struct Case {
  std::string name;
  std::string service;
  std::function<std::vector<std::uint8_t>()> bytes;
  std::optional<std::int8_t> status;  // nullopt: dropped without a reply
};

integrate_request_t modified(const std::function<void(integrate_request_t&)>& change) {
  integrate_request_t request = scan("robot1", 10, 0.5);
  change(request);
  return request;
}

std::vector<Case> cases() {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  using R = reply_header_t;
  const std::string kInt(channels::kIntegrate);
  return {
      {"empty message", kInt, [] { return std::vector<std::uint8_t>{}; }, std::nullopt},
      {"garbage", kInt, [] { return std::vector<std::uint8_t>(300, 0xA5); }, std::nullopt},
      {"truncated", kInt,
       [] {
         auto b = test::encode(scan("robot1", 10));
         b.resize(b.size() / 2);
         return b;
       },
       std::nullopt},
      {"trailing bytes", kInt,
       [] {
         auto b = test::encode(scan("robot1", 10));
         b.push_back(0);
         return b;
       },
       std::nullopt},
      {"wrong fingerprint (chunk request on INTEGRATE)", kInt,
       [] { return test::encode(test::everything()); }, std::nullopt},
      {"wrong fingerprint (integrate on GET_STATS)", std::string(channels::kGetStats),
       [] { return test::encode(scan("robot1", 10)); }, std::nullopt},
      {"num_points claims 2^31-1", kInt,
       [] {
         const auto r = scan("robot1", 10);
         auto b = test::encode(r);
         putInt32(b, numPointsOffset(r), std::numeric_limits<std::int32_t>::max());
         return b;
       },
       std::nullopt},
      {"negative num_points", kInt,
       [] {
         const auto r = scan("robot1", 10);
         auto b = test::encode(r);
         putInt32(b, numPointsOffset(r), -4);
         return b;
       },
       std::nullopt},
      {"negative string length", kInt,
       [] {
         auto b = test::encode(scan("robot1", 10));
         putInt32(b, 16, -7);  // client_id length, after hash and request_id
         return b;
       },
       std::nullopt},
      {"invalid client id", kInt,
       [] {
         auto r = scan("robot1", 10);
         r.header.client_id = "bad id/../x";
         r.header.reply_channel = "SOCC/INTEGRATE/REP/bad id/../x";
         return test::encode(r);
       },
       std::nullopt},
      {"reply channel of another client", kInt,
       [] {
         auto r = scan("robot1", 10);
         r.header.reply_channel = "SOCC/INTEGRATE/REP/victim";
         return test::encode(r);
       },
       +R::INVALID_ARGUMENT},
      {"NaN point resolution", kInt,
       [nan] { return test::encode(modified([&](auto& r) { r.xyz_resolution = nan; })); },
       +R::INVALID_ARGUMENT},
      {"inf point resolution", kInt,
       [inf] { return test::encode(modified([&](auto& r) { r.xyz_resolution = inf; })); },
       +R::INVALID_ARGUMENT},
      {"zero point resolution", kInt,
       [] { return test::encode(modified([](auto& r) { r.xyz_resolution = 0.f; })); },
       +R::INVALID_ARGUMENT},
      {"absurd point", kInt,
       [] { return test::encode(modified([](auto& r) { r.xyz_resolution = 1e6f; })); },
       +R::INVALID_ARGUMENT},
      {"NaN pose", kInt,
       [] {
         return test::encode(modified([](auto& r) { r.sensor_pose.quaternion[2] = std::nan(""); }));
       },
       +R::INVALID_ARGUMENT},
      {"absurd pose", kInt,
       [] { return test::encode(modified([](auto& r) { r.sensor_pose.translation[0] = 1e12; })); },
       +R::INVALID_ARGUMENT},
      {"non-unit quaternion", kInt,
       [] { return test::encode(modified([](auto& r) { r.sensor_pose.quaternion[0] = 3.0; })); },
       +R::INVALID_ARGUMENT},
      {"unknown label", kInt,
       [] { return test::encode(modified([](auto& r) { r.label[7] = 20; })); },
       +R::INVALID_ARGUMENT},
      {"label count != point count", kInt,
       [] {
         return test::encode(modified([](auto& r) {
           r.label.resize(3);
           r.num_labels = 3;
         }));
       },
       +R::INVALID_ARGUMENT},
      {"time count != point count", kInt,
       [] {
         return test::encode(modified([](auto& r) {
           r.time.assign(2, 0.0f);
           r.num_times = 2;
         }));
       },
       +R::INVALID_ARGUMENT},
      {"NaN gravity_sigma", kInt,
       [nan] { return test::encode(modified([&](auto& r) { r.gravity_sigma = nan; })); },
       +R::INVALID_ARGUMENT},
      {"negative gravity_sigma", kInt,
       [] { return test::encode(modified([](auto& r) { r.gravity_sigma = -0.001f; })); },
       +R::INVALID_ARGUMENT},
      {"gravity_sigma above 0.5 rad", kInt,
       [] { return test::encode(modified([](auto& r) { r.gravity_sigma = 0.6f; })); },
       +R::INVALID_ARGUMENT},
      {"non-unit gravity_up", kInt,
       [] {
         return test::encode(modified([](auto& r) {
           r.gravity_up[2] = 1.02f;
           r.gravity_sigma = 0.001f;
         }));
       },
       +R::INVALID_ARGUMENT},
      {"zero gravity_up", kInt,
       [] { return test::encode(modified([](auto& r) { r.gravity_sigma = 0.001f; })); },
       +R::INVALID_ARGUMENT},
      {"NaN gravity_up", kInt,
       [nan] {
         return test::encode(modified([&](auto& r) {
           r.gravity_up[0] = nan;
           r.gravity_up[2] = 1.f;
           r.gravity_sigma = 0.001f;
         }));
       },
       +R::INVALID_ARGUMENT},
      {"negative seq", kInt, [] { return test::encode(modified([](auto& r) { r.seq = -1; })); },
       +R::INVALID_ARGUMENT},
      {"too many points", kInt,
       [] {
         return test::encode(modified([](auto& r) {
           for (int axis = 0; axis < 3; ++axis)
             r.xyz[axis].resize(6000, static_cast<std::int16_t>(100 * (axis + 1)));
           r.label.resize(6000, 0);
           r.num_points = r.num_labels = 6000;
         }));
       },
       +R::RESOURCE_EXHAUSTED},
      {"chunk with NaN centre", std::string(channels::kGetChunk),
       [] {
         auto c = test::everything();
         c.header.reply_channel = channels::reply(channels::kGetChunk, "tester");
         c.center[0] = std::nan("");
         return test::encode(c);
       },
       +R::INVALID_ARGUMENT},
      {"unknown tracking state", std::string(channels::kRobotStatus),
       [] { return test::encode(test::trackingReport("robot1", 9, 1)); }, +R::INVALID_ARGUMENT},
      {"tracking report of another robot's channel", std::string(channels::kRobotStatus),
       [] {
         auto r = test::trackingReport("robot1", robot_status_request_t::LOST, 1);
         r.header.reply_channel = channels::reply(channels::kRobotStatus, "victim");
         return test::encode(r);
       },
       +R::INVALID_ARGUMENT},
      {"tracking report of an unknown robot", std::string(channels::kRobotStatus),
       [] { return test::encode(test::trackingReport("ghost", robot_status_request_t::LOST, 1)); },
       +R::NOT_FOUND},
      {"damaged tracking report", std::string(channels::kRobotStatus),
       [] {
         auto b = test::encode(test::trackingReport("robot1", robot_status_request_t::LOST, 1));
         b.resize(b.size() - 3);
         return b;
       },
       std::nullopt},
      {"command path escapes", std::string(channels::kMapCommand),
       [] {
         map_command_request_t c{};
         c.header.client_id = "tester";
         c.header.reply_channel = channels::reply(channels::kMapCommand, "tester");
         c.command = map_command_request_t::SAVE;
         c.path = "../../etc/evil";
         return test::encode(c);
       },
       +R::INVALID_ARGUMENT},
  };
}

TEST(MalformedRequests, RejectedAndMapUnchanged) {
  RouterHarness harness(test::smallConfig());
  harness.send(std::string(channels::kIntegrate), test::encode(scan("robot1", 1)));
  ASSERT_EQ(harness.replies.size(), 1u);
  ASSERT_EQ(headerOf(harness.replies[0])->status, +reply_header_t::OK);

  const std::int64_t version = harness.service.map().version();
  const auto content = test::content(harness.service.getChunk(test::everything()));
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    harness.replies.clear();
    const std::int64_t rejected = harness.router.counters().rejected;
    harness.send(c.service, c.bytes());
    EXPECT_EQ(harness.router.counters().rejected, rejected + 1);
    if (!c.status) {
      EXPECT_TRUE(harness.replies.empty());
    } else {
      ASSERT_EQ(harness.replies.size(), 1u);
      const auto header = headerOf(harness.replies[0]);
      ASSERT_TRUE(header);
      EXPECT_EQ(header->status, *c.status) << header->message;
      EXPECT_FALSE(header->message.empty());
      // Replies only ever go to the requester's own channel.
      EXPECT_EQ(harness.replies[0].channel.rfind("SOCC/" + c.service + "/REP/", 0), 0u);
      EXPECT_EQ(harness.replies[0].channel.find("victim"), std::string::npos);
    }
    EXPECT_EQ(harness.service.map().version(), version);
    EXPECT_EQ(test::content(harness.service.getChunk(test::everything())), content);
  }
  EXPECT_GT(harness.router.counters().decode_failures, 5);

  // Still serving after all of it.
  harness.replies.clear();
  harness.send(std::string(channels::kIntegrate), test::encode(scan("robot1", 2)));
  ASSERT_EQ(harness.replies.size(), 1u);
  EXPECT_EQ(headerOf(harness.replies[0])->status, +reply_header_t::OK);
  EXPECT_GT(harness.service.map().version(), version);
}

TEST(MalformedRequests, GravityReferenceAcceptedAndNamedWhenRefused) {
  RouterHarness harness(test::smallConfig());
  integrate_request_t with = scan("robot1", 1);
  with.gravity_up[0] = 0.6f;  // any unit direction: the sensor may be mounted tilted
  with.gravity_up[2] = 0.8f;
  with.gravity_sigma = 0.0006f;
  harness.send(std::string(channels::kIntegrate), test::encode(with));
  integrate_request_t unused = scan("robot1", 2, 0.5);
  unused.gravity_up[0] = std::numeric_limits<float>::quiet_NaN();  // sigma 0: not read
  harness.send(std::string(channels::kIntegrate), test::encode(unused));
  integrate_request_t bad = scan("robot1", 3, 1.0);
  bad.gravity_up[2] = 2.f;
  bad.gravity_sigma = 0.001f;
  harness.send(std::string(channels::kIntegrate), test::encode(bad));
  ASSERT_EQ(harness.replies.size(), 3u);
  EXPECT_EQ(headerOf(harness.replies[0])->status, +reply_header_t::OK);
  EXPECT_EQ(headerOf(harness.replies[1])->status, +reply_header_t::OK);
  const auto refused = headerOf(harness.replies[2]);
  EXPECT_EQ(refused->status, +reply_header_t::INVALID_ARGUMENT);
  EXPECT_NE(refused->message.find("gravity_up must be a unit vector"), std::string::npos)
      << refused->message;
}

TEST(MalformedRequests, RandomBytesNeverCrash) {
  RouterHarness harness(test::smallConfig());
  const auto valid = test::encode(scan("robot1", 1));
  std::mt19937 rng(7);
  for (int i = 0; i < 300; ++i) {
    auto bytes = valid;
    // Flip a few bytes, often in the header and count fields where damage is most dangerous.
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = (i % 2 == 0) ? rng() % 120 : rng() % bytes.size();
      bytes[at] = static_cast<std::uint8_t>(rng());
    }
    harness.send(std::string(channels::kIntegrate), bytes);
  }
  EXPECT_EQ(harness.router.counters().requests, 300);
}

TEST(MalformedRequests, StatusIsPublished) {
  RouterHarness harness(test::smallConfig());
  bool got = false;
  const auto on_status = [](const lcm_recv_buf_t* rbuf, const char*, void* flag) {
    map_stats_t stats;
    *static_cast<bool*>(flag) = stats.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0;
  };
  lcm_subscribe(harness.lcm.getUnderlyingLCM(), std::string(channels::kStatus).c_str(), on_status,
                &got);
  harness.router.publishStatus();
  while (harness.lcm.handleTimeout(0) > 0) {
  }
  EXPECT_TRUE(got);
}

}  // namespace
}  // namespace socc::service
