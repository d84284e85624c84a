#include <gtest/gtest.h>

#include "socc/lcm_url.hpp"

TEST(LcmUrl, OnlyLocalMulticastOrMemq) {
  EXPECT_TRUE(socc::checkLcmUrl("udpm://239.255.76.67:7667?ttl=0").empty());
  EXPECT_TRUE(socc::checkLcmUrl("udpm://239.1.2.3:7000?recv_buf_size=8000000&ttl=0").empty());
  EXPECT_TRUE(socc::checkLcmUrl("memq://").empty());
  EXPECT_FALSE(socc::checkLcmUrl("udpm://239.255.76.67:7667?ttl=1").empty());
  EXPECT_FALSE(socc::checkLcmUrl("udpm://239.255.76.67:7667").empty());
  EXPECT_FALSE(socc::checkLcmUrl("udpm://224.0.0.1:7667?ttl=0").empty());
  EXPECT_FALSE(socc::checkLcmUrl("tcpq://10.0.0.1:7700").empty());
}
