#pragma once
// The C++ tests' counterpart of test_env.sh's random_lcm_url: a random 239.255.x.y group and
// port, ttl=0 (multicast routed to loopback: nothing leaves the machine), so concurrent test
// runs never see each other's traffic.
#include <unistd.h>

#include <random>
#include <string>

namespace socc::testing {

inline std::string randomLoopbackLcmUrl(int base_port = 30000) {
  std::random_device rd;
  std::mt19937 rng(rd() ^ static_cast<unsigned>(::getpid()));
  return "udpm://239.255." + std::to_string(rng() % 250 + 1) + "." +
         std::to_string(rng() % 250 + 1) + ":" + std::to_string(base_port + rng() % 10000) +
         "?ttl=0&recv_buf_size=67108864";
}

}  // namespace socc::testing
