#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <thread>

#include "socc/auth/message_auth.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/map_command_request_t.hpp"

namespace socc::auth {
namespace {

SharedKey keyOf(std::uint8_t fill) {
  return SharedKey::fromBytes(std::vector<std::uint8_t>(32, fill));
}

integrate_request_t makeRequest() {
  integrate_request_t r{};
  r.header.request_id = 7;
  r.header.client_id = "robot1";
  r.header.reply_channel = "SOCC/INTEGRATE/REP/robot1";
  r.seq = 3;
  r.sensor_pose.quaternion[0] = 1.0;
  r.num_points = 2;
  r.xyz_resolution = 0.01f;
  r.xyz = {{100, 400}, {200, 500}, {300, 600}};  // points (1, 2, 3) and (4, 5, 6) m by axis
  r.num_labels = 2;
  r.label = {9, 13};
  return r;
}

TEST(MessageAuth, SignVerifyRoundTrip) {
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 100);
  EXPECT_EQ(r.header.auth_counter, 100);
  EXPECT_EQ(r.header.mac_len, 32);
  Verifier v(keyOf(1));
  const AuthResult res = v.verify(r);
  EXPECT_TRUE(res.ok) << res.reason;
  EXPECT_EQ(v.replayGuard().counters().at("robot1"), 100);
}

TEST(MessageAuth, SurvivesEncodeDecode) {
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 5);
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(r.getEncodedSize()));
  ASSERT_EQ(r.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  integrate_request_t decoded{};
  ASSERT_GT(decoded.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
  Verifier v(keyOf(1));
  EXPECT_TRUE(v.verify(decoded).ok);
}

std::vector<std::uint8_t> encode(const integrate_request_t& r) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(r.getEncodedSize()));
  EXPECT_EQ(r.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

TEST(MessageAuth, VerifyEncodedBytesAsReceived) {
  // What a server's admission gate sees: the raw bytes and the decoded header.
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 10);
  std::vector<std::uint8_t> bytes = encode(r);
  Verifier v(keyOf(1));
  AuthResult res = v.verifyEncoded(r.header, bytes.data(), bytes.size());
  EXPECT_TRUE(res.ok) << res.reason;
  EXPECT_EQ(v.verifyEncoded(r.header, bytes.data(), bytes.size()).failure, AuthFailure::kReplayed);

  sign(r, keyOf(1), 11);
  bytes = encode(r);
  bytes[bytes.size() - 5] ^= 0x40;  // a flipped payload bit
  EXPECT_EQ(v.verifyEncoded(r.header, bytes.data(), bytes.size()).failure, AuthFailure::kBadMac);
  // A header that is not the one in the bytes, and truncated bytes.
  integrate_request_t other = r;
  other.header.mac[0] ^= 1;
  EXPECT_EQ(v.verifyEncoded(other.header, bytes.data(), bytes.size()).failure,
            AuthFailure::kMalformedMac);
  EXPECT_EQ(v.verifyEncoded(r.header, bytes.data(), 20).failure, AuthFailure::kMalformedMac);
  EXPECT_EQ(v.verifyEncoded(r.header, nullptr, 0).failure, AuthFailure::kMalformedMac);
}

TEST(MessageAuth, ForgedMacRejected) {
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 1);
  r.header.mac[5] ^= 0x01;
  Verifier v(keyOf(1));
  const AuthResult res = v.verify(r);
  EXPECT_FALSE(res.ok);
  EXPECT_EQ(res.failure, AuthFailure::kBadMac);
  EXPECT_TRUE(v.replayGuard().counters().empty()) << "a rejected request must not move the counter";
}

TEST(MessageAuth, TamperedPayloadRejected) {
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 1);
  r.xyz[2][1] = 6000;  // z of point 1
  EXPECT_EQ(Verifier(keyOf(1)).verify(r).failure, AuthFailure::kBadMac);

  integrate_request_t other_client = makeRequest();
  sign(other_client, keyOf(1), 1);
  other_client.header.client_id = "robot2";  // impersonation by rewriting the header
  EXPECT_EQ(Verifier(keyOf(1)).verify(other_client).failure, AuthFailure::kBadMac);
}

TEST(MessageAuth, WrongKeyRejected) {
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 1);
  EXPECT_EQ(Verifier(keyOf(2)).verify(r).failure, AuthFailure::kBadMac);
}

TEST(MessageAuth, MacBoundToRequestType) {
  // Same header bytes in another request type: the type hash is part of the signed encoding.
  map_command_request_t cmd{};
  cmd.header = makeRequest().header;
  cmd.command = map_command_request_t::CLEAR;
  sign(cmd, keyOf(1), 9);
  integrate_request_t r = makeRequest();
  r.header = cmd.header;
  EXPECT_EQ(Verifier(keyOf(1)).verify(r).failure, AuthFailure::kBadMac);
}

TEST(MessageAuth, ReplayedAndLowerCountersRejected) {
  Verifier v(keyOf(1));
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), 50);
  ASSERT_TRUE(v.verify(r).ok);

  const AuthResult replay = v.verify(r);
  EXPECT_FALSE(replay.ok);
  EXPECT_EQ(replay.failure, AuthFailure::kReplayed);

  integrate_request_t older = makeRequest();
  sign(older, keyOf(1), 49);
  const AuthResult stale = v.verify(older);
  EXPECT_EQ(stale.failure, AuthFailure::kStale);
  EXPECT_NE(stale.reason, replay.reason);

  integrate_request_t newer = makeRequest();
  sign(newer, keyOf(1), 51);
  EXPECT_TRUE(v.verify(newer).ok);

  // Counters are per client: another robot may start lower.
  integrate_request_t robot2 = makeRequest();
  robot2.header.client_id = "robot2";
  sign(robot2, keyOf(1), 2);
  EXPECT_TRUE(v.verify(robot2).ok);
}

TEST(MessageAuth, MissingAndMalformedMacRejected) {
  Verifier v(keyOf(1));
  integrate_request_t r = makeRequest();
  const AuthResult missing = v.verify(r);
  EXPECT_EQ(missing.failure, AuthFailure::kMissingMac);

  sign(r, keyOf(1), 3);
  integrate_request_t short_mac = r;
  short_mac.header.mac.resize(16);
  short_mac.header.mac_len = 16;
  EXPECT_EQ(v.verify(short_mac).failure, AuthFailure::kMalformedMac);

  integrate_request_t lying_len = r;
  lying_len.header.mac_len = 64;  // inconsistent with the vector: never read past it
  EXPECT_EQ(v.verify(lying_len).failure, AuthFailure::kMalformedMac);

  integrate_request_t zero_counter = makeRequest();
  sign(zero_counter, keyOf(1), 0);
  EXPECT_EQ(v.verify(zero_counter).failure, AuthFailure::kBadCounter);

  const std::set<AuthFailure> distinct = {missing.failure, AuthFailure::kMalformedMac,
                                          AuthFailure::kBadMac, AuthFailure::kReplayed,
                                          AuthFailure::kStale};
  EXPECT_EQ(distinct.size(), 5u);
  EXPECT_EQ(toString(AuthFailure::kReplayed), "replayed");
}

TEST(MessageAuth, ResignedRetryAccepted) {
  // The client retries the same request (same request_id/seq) after a timeout: re-signed
  // with a new counter it passes; resent unchanged it is a replay.
  Verifier v(keyOf(1));
  AuthCounter counter(1000);
  integrate_request_t r = makeRequest();
  sign(r, keyOf(1), counter.next());
  ASSERT_TRUE(v.verify(r).ok);
  EXPECT_EQ(v.verify(r).failure, AuthFailure::kReplayed);
  sign(r, keyOf(1), counter.next());
  EXPECT_TRUE(v.verify(r).ok);
}

TEST(AuthCounter, StrictlyIncreasingFromWallClock) {
  AuthCounter c;
  const std::int64_t a = c.next();
  const std::int64_t b = c.next();
  EXPECT_GT(b, a);
  EXPECT_GT(a, 1'600'000'000'000'000);  // microseconds since epoch, after 2020
  std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a restart takes longer
  AuthCounter restarted;
  EXPECT_GT(restarted.next(), b);
  AuthCounter far_ahead(std::int64_t{1} << 62);
  EXPECT_EQ(far_ahead.next(), (std::int64_t{1} << 62) + 1);
}

TEST(Hmac, KnownAnswerRfc4231Case6) {
  // RFC 4231 test case 6: 131-byte key of 0xaa (a key length we accept).
  const SharedKey k = SharedKey::fromBytes(std::vector<std::uint8_t>(131, 0xaa));
  const std::string data = "Test Using Larger Than Block-Size Key - Hash Key First";
  const Mac mac = hmacSha256(k, reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
  const Mac expected = {0x60, 0xe4, 0x31, 0x59, 0x1e, 0xe0, 0xb6, 0x7f, 0x0d, 0x8a, 0x26,
                        0xaa, 0xcb, 0xf5, 0xb7, 0x7f, 0x8e, 0x0b, 0xc6, 0x21, 0x37, 0x28,
                        0xc5, 0x14, 0x05, 0x46, 0x04, 0x0f, 0x0e, 0xe3, 0x7f, 0x54};
  EXPECT_EQ(mac, expected);
  EXPECT_TRUE(macEqual(mac, expected.data()));
  Mac other = expected;
  other[31] ^= 1;
  EXPECT_FALSE(macEqual(mac, other.data()));
}

}  // namespace
}  // namespace socc::auth
