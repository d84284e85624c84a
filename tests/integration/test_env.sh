#!/usr/bin/env bash
# Sourced by the test scripts that run real processes over LCM UDP multicast on loopback.

# Fails (exit 1) with the fix when multicast is not routed to loopback: without the route,
# udpm traffic could not stay on this machine.
require_multicast_on_loopback() {
  if ! ip route show 224.0.0.0/4 2>/dev/null | grep -q "dev lo"; then
    echo "FAIL: multicast is not routed to loopback, so LCM udpm traffic cannot stay local."
    echo "      Enable it with: sudo ip route replace 224.0.0.0/4 dev lo   (scripts/setup.sh does this)"
    exit 1
  fi
}

# random_lcm_url BASE: a random 239.255.x.y group and a port in [BASE, BASE + 9999], ttl=0, so
# concurrent test runs never see each other's traffic and nothing leaves the machine.
random_lcm_url() {
  local seed=$(( ((RANDOM << 15) | RANDOM) ^ $$ ))
  echo "udpm://239.255.$((seed / 10000 % 250 + 1)).$((seed / 2500000 % 250 + 1)):$(($1 + seed % 10000))?ttl=0&recv_buf_size=67108864"
}
