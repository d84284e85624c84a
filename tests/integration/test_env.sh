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

# make_work_dir: a scratch directory in $work. At exit every background job of the calling
# script is stopped and $work removed, unless keep_work=1 then (a script sets keep_work=1 while
# it runs and 0 when it passed, so a failed run keeps its logs: "work dir kept: ...").
make_work_dir() {
  work=$(mktemp -d)
  keep_work=0
  trap _stop_jobs_and_clean_work EXIT
  trap 'exit 130' INT TERM
}
# shellcheck disable=SC2317  # called by the EXIT trap
_stop_jobs_and_clean_work() {
  local p
  # The shell's own background jobs that have not been waited for yet (never a reaped pid).
  for p in $(jobs -p); do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  if ((keep_work)); then echo "work dir kept: $work"; else rm -rf "$work"; fi
}

# kitti_pose POSES FRAME: row FRAME (from 0) of a KITTI poses file as odom_client's
# --initial-pose "x y z roll pitch yaw" (R = Rz Ry Rx).
kitti_pose() {
  sed -n "$(($2 + 1))p" "$1" | awk '{
    printf "%.9f %.9f %.9f %.12f %.12f %.12f", $4, $8, $12,
      atan2($10, $11), atan2(-$9, sqrt($10 * $10 + $11 * $11)), atan2($5, $1) }'
}

# realism_odom_config LEVEL: the odom_client config layer for socc-sim's --realism LEVEL, empty
# when there is none. kitti: the preset bends every beam 0.22 deg in elevation, as KITTI's HDL-64
# does, and odom_client/config/kitti.yaml undoes it as the peers' KITTI loaders do (sim/README.md
# "Realism"); a method's own config is layered after it (odom_client --config A --config B).
realism_odom_config() {
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/odom_client/config"
  case "$1" in kitti) echo "$dir/kitti.yaml" ;; esac
}
