#include <gtest/gtest.h>

#include "socc/lcm_url.hpp"

namespace {

using socc::checkLcmUrl;
using socc::LcmAuth;

bool allowed(const std::string& url, LcmAuth auth = LcmAuth::kNoKey) {
  return checkLcmUrl(url, auth).empty();
}

}  // namespace

TEST(LcmUrl, OnlyLocalMulticastOrMemq) {
  EXPECT_TRUE(allowed("udpm://239.255.76.67:7667?ttl=0"));
  EXPECT_TRUE(allowed("udpm://239.1.2.3:7000?recv_buf_size=8000000&ttl=0"));
  EXPECT_TRUE(allowed("memq://"));
  EXPECT_FALSE(allowed("udpm://239.255.76.67:7667?ttl=1"));
  EXPECT_FALSE(allowed("udpm://239.255.76.67:7667"));
  EXPECT_FALSE(allowed("udpm://224.0.0.1:7667?ttl=0"));
  EXPECT_FALSE(allowed("tcpq://10.0.0.1:7700"));
}

TEST(LcmUrl, LoopbackNeedsNoKey) {
  EXPECT_TRUE(allowed("udpm://239.255.76.67:7667?ttl=0", LcmAuth::kKeyConfigured));
  EXPECT_TRUE(allowed("memq://", LcmAuth::kKeyConfigured));
  EXPECT_EQ(socc::lcmAuthFor(""), LcmAuth::kNoKey);
  EXPECT_EQ(socc::lcmAuthFor("/etc/socc/map.key"), LcmAuth::kKeyConfigured);
}

TEST(LcmUrl, LanOnlyWithKey) {
  const std::string lan = "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=33554432";
  EXPECT_TRUE(allowed(lan, LcmAuth::kKeyConfigured));
  const std::string why = checkLcmUrl(lan, LcmAuth::kNoKey);
  EXPECT_NE(why.find("ttl=1 (LAN) needs an HMAC key"), std::string::npos) << why;
  EXPECT_NE(why.find("--key-file"), std::string::npos) << why;
}

TEST(LcmUrl, NothingBeyondOneLan) {
  for (const char* url : {"udpm://239.255.76.67:7667?ttl=2", "udpm://239.255.76.67:7667?ttl=255",
                          "udpm://239.255.76.67:7667?ttl=01",
                          "udpm://239.255.76.67:7667?ttl=", "udpm://239.255.76.67:7667?ttl=-1"})
    EXPECT_FALSE(allowed(url, LcmAuth::kKeyConfigured)) << url;
  EXPECT_NE(checkLcmUrl("udpm://239.1.1.1:7667?ttl=2", LcmAuth::kKeyConfigured).find("routers"),
            std::string::npos);
}

TEST(LcmUrl, ExactlyOneTtlOption) {
  // Two ttl options: which one LCM applies is not ours to guess, so neither is accepted.
  EXPECT_FALSE(allowed("udpm://239.1.2.3:7000?ttl=0&ttl=1", LcmAuth::kKeyConfigured));
  EXPECT_FALSE(allowed("udpm://239.1.2.3:7000?ttl=0&ttl=0"));
  EXPECT_FALSE(allowed("udpm://239.1.2.3:7000?recv_buf_size=8000000"));
  EXPECT_FALSE(allowed("udpm://239.1.2.3:7000?xttl=0"));
}

TEST(LcmUrl, KeyDoesNotOpenOtherTransports) {
  EXPECT_FALSE(allowed("udpm://224.0.0.1:7667?ttl=1", LcmAuth::kKeyConfigured));
  EXPECT_FALSE(allowed("tcpq://10.0.0.1:7700", LcmAuth::kKeyConfigured));
  EXPECT_FALSE(allowed("udpm://239.1.2.3?ttl=1", LcmAuth::kKeyConfigured));
}

TEST(LcmUrl, LanUrlsAreRecognised) {
  EXPECT_TRUE(socc::isLanLcmUrl("udpm://239.255.76.67:7667?ttl=1&recv_buf_size=33554432"));
  EXPECT_FALSE(socc::isLanLcmUrl("udpm://239.255.76.67:7667?ttl=0"));
  EXPECT_FALSE(socc::isLanLcmUrl("udpm://239.255.76.67:7667?ttl=0&ttl=1"));
  EXPECT_FALSE(socc::isLanLcmUrl("memq://"));
}
