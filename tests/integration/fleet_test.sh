#!/usr/bin/env bash
# Fleet test (issue 14): map_server and two robots on separate hosts of one LAN, in network
# namespaces this test creates (fleet_netns.sh: hosts server, robot1, robot2, intruder joined by
# a bridge inside a namespace; nothing touches a real interface) and deletes at the end, also
# on failure. LCM runs in LAN mode: udpm://239.255.x.y:port?ttl=1 with a shared key.
#
# Usage: fleet_test.sh --server BIN --client BIN --cli BIN --sim BIN [--frames N] [--loss PCT]
#                      [--csv FILE] [--keep]
#   The robots drive consecutive N-frame segments (default 4) of one socc-sim street (HDL-64:
#   KITTI-size scans, 1.6 MB per INTEGRATE) from their GT start poses, at the same time.
#   Checks: both robots exit 0 with N poses; `socc-cli stats` run on robot2's host lists both
#   robots, each with its last seq and exactly N integrations (each scan applied once); an
#   intruder host without the key cannot even open the LAN URL, and with a wrong key gets
#   UNAUTHENTICATED for socc-cli and odom_client; afterwards the map digest is unchanged,
#   the intruder is not listed and auth_failures counts its requests.
#   --loss PCT drops PCT % of the IP packets (each fragment alone) in and out of each robot
#   host (nftables); --csv appends one line per robot: loss,robot,frames,Hz,fetch/integrate ms.
#   --keep keeps the work directory (logs, frames.csv of each robot) also when the test passes.
# Needs root (CAP_NET_ADMIN) and nft for --loss; without them it FAILS (it never skips).
set -euo pipefail
usage() { sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

server_bin="" client_bin="" cli_bin="" sim_bin="" frames=4 loss=0 csv="" keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --server) server_bin=$2; shift 2 ;;
    --client) client_bin=$2; shift 2 ;;
    --cli) cli_bin=$2; shift 2 ;;
    --sim) sim_bin=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --loss) loss=$2; shift 2 ;;
    --csv) csv=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) usage 0 ;;
    *) echo "fleet_test: unknown argument $1" >&2; usage 2 ;;
  esac
done
for b in "$server_bin" "$client_bin" "$cli_bin" "$sim_bin"; do
  [[ -x $b ]] || { echo "FAIL: binary '$b' missing (--server/--client/--cli/--sim)"; exit 2; }
done

here=$(dirname "$0")
# shellcheck source=fleet_netns.sh
source "$here/fleet_netns.sh"

fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
prefix="socc-fleet-$$-$RANDOM"
keep_work=1
# shellcheck disable=SC2317  # called by the EXIT trap
cleanup() {
  netns_lan_delete "$prefix"
  wait 2>/dev/null || true
  if ((keep_work)); then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

seed=$(((RANDOM << 15 | RANDOM) ^ $$))
url="udpm://239.255.$((seed % 250 + 1)).$((seed / 250 % 250 + 1)):$((20000 + seed % 10000))?ttl=1&recv_buf_size=67108864"
key=$work/fleet.key
wrong=$work/wrong.key
(umask 077 && head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' >"$key")
(umask 077 && head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' >"$wrong")

cli_on() {  # cli_on HOST [socc-cli args]: socc-cli with the fleet key on HOST
  local host=$1
  shift
  in_host "$prefix" "$host" "$cli_bin" --lcm-url "$url" --key-file "$key" --client-id "ops-$host" "$@"
}

make_lan() {
  if ! netns_lan_create "$prefix" server robot1 robot2 intruder 2>"$work/netns.log"; then
    fail "cannot create network namespaces (needs root / CAP_NET_ADMIN): $(cat "$work/netns.log")"
  fi
  if [[ $loss != 0 ]]; then
    command -v nft >/dev/null || fail "--loss needs nft (Debian package nftables)"
    local host
    for host in robot1 robot2; do
      netns_lan_loss "$prefix" "$host" "$loss" || fail "cannot install the nftables loss rules"
    done
  fi
  echo "LAN: namespaces $prefix-{lan,server,robot1,robot2,intruder}, $url, loss $loss % on robot links"
}

start_server() {
  in_host "$prefix" server "$server_bin" --lcm-url "$url" --key-file "$key" --status-period 0 \
    --snapshot-dir "$work/state" --journal "$work/state/journal.lcmlog" --quiet \
    >"$work/server.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 100); do
    cli_on robot1 --timeout-ms 200 --attempts 1 stats >/dev/null 2>&1 && return 0
    kill -0 "$server_pid" 2>/dev/null || fail "map_server exited: $(cat "$work/server.log")"
    sleep 0.1
  done
  fail "map_server on the server host does not answer robot1's host within 10 s"
}

gt_pose() {  # gt_pose FRAME: GT pose of FRAME as "x y z roll pitch yaw" (R = Rz Ry Rx)
  sed -n "$(($1 + 1))p" "$work/sim/poses.txt" | awk '{
    printf "%.9f %.9f %.9f %.12f %.12f %.12f", $4, $8, $12,
      atan2($10, $11), atan2(-$9, sqrt($10 * $10 + $11 * $11)), atan2($5, $1) }'
}

# On a lossy LAN a lost small request or reply (one packet) costs one attempt's timeout: 500 ms
# instead of the default 2 s (docs/fleet.md), with attempts enough for several losses in a row.
printf 'timeout_ms: 500\nmax_attempts: 20\n' >"$work/lan.yaml"

run_robot() {  # run_robot HOST ROBOT_ID FIRST KEY: odom_client on frames FIRST.. on HOST
  in_host "$prefix" "$1" "$client_bin" --kitti "$work/sim" --config "$work/lan.yaml" --first-frame "$3" \
    --last-frame $(($3 + frames - 1)) --initial-pose "$(gt_pose "$3")" --lcm-url "$url" \
    --key-file "$4" --robot-id "$2" --out-dir "$work/$2" --quiet >"$work/$2.log" 2>&1
}

robots_map_together() {
  "$sim_bin" --out "$work/sim" --frames $((2 * frames)) --seed 7 --quiet >/dev/null || fail "socc-sim failed"
  local start=$SECONDS
  run_robot robot1 car1 0 "$key" &
  local pid1=$!
  run_robot robot2 car2 "$frames" "$key" &
  local pid2=$!
  wait "$pid1" || fail "car1 (robot1 host) failed: $(tail -5 "$work/car1.log")"
  wait "$pid2" || fail "car2 (robot2 host) failed: $(tail -5 "$work/car2.log")"
  echo "two robots on two hosts: $frames frames each in $((SECONDS - start)) s"
  local car
  for car in car1 car2; do
    [[ $(wc -l <"$work/$car/poses_kitti.txt") == "$frames" ]] || fail "$car wrote no $frames poses"
  done
}

check_stats_from_robot_host() {
  cli_on robot2 stats | tee "$work/stats.txt" | sed 's/^/  stats (robot2 host): /'
  grep -q " robots=2$" "$work/stats.txt" || fail "GET_STATS from robot2's host does not list 2 robots"
  grep -q "^car1 seq=$((frames - 1)) integrations=$frames " "$work/stats.txt" ||
    fail "car1: expected last seq $((frames - 1)) and $frames integrations (each scan once)"
  grep -q "^car2 seq=$((2 * frames - 1)) integrations=$frames " "$work/stats.txt" ||
    fail "car2: expected last seq $((2 * frames - 1)) and $frames integrations (each scan once)"
}

map_digest() {
  cli_on robot1 chunk --sphere 0 0 0 150 --fields features stats free index --digest |
    sed -n 's/^digest=//p'
}

intruder_is_refused() {
  local before out rc
  before=$(map_digest)
  [[ -n $before ]] || fail "chunk digest from robot1's host failed"
  # No key: the LAN URL is refused before any socket is opened.
  if out=$(in_host "$prefix" intruder "$cli_bin" --lcm-url "$url" stats 2>&1); then
    fail "socc-cli without a key used the LAN URL: $out"
  fi
  grep -q "ttl=1 (LAN) needs an HMAC key" <<<"$out" || fail "no-key refusal says: $out"
  # Wrong key: a scan far from the robots, and a whole odom_client run.
  out=$(in_host "$prefix" intruder "$cli_bin" --lcm-url "$url" --key-file "$wrong" \
    --client-id intruder integrate --seq 1 --pose 40 40 0 0 2>&1) && fail "intruder's INTEGRATE accepted: $out"
  grep -q "UNAUTHENTICATED" <<<"$out" || fail "intruder's INTEGRATE: expected UNAUTHENTICATED, got: $out"
  rc=0
  run_robot intruder intruder 0 "$wrong" || rc=$?
  ((rc != 0)) || fail "odom_client with a wrong key exited 0"
  grep -q "UNAUTHENTICATED" "$work/intruder.log" ||
    fail "odom_client with a wrong key: no UNAUTHENTICATED: $(tail -3 "$work/intruder.log")"
  echo "intruder: no key -> refused locally; wrong key -> UNAUTHENTICATED (socc-cli, odom_client exit $rc)"
  [[ $(map_digest) == "$before" ]] || fail "the intruder changed the map"
  cli_on robot2 stats >"$work/stats_after.txt"
  grep -q " robots=2$" "$work/stats_after.txt" || fail "robots changed after the intruder"
  grep -q "^intruder " "$work/stats_after.txt" && fail "the intruder is listed as a robot"
  local failures
  failures=$(sed -n '1s/.* auth_failures=\([0-9]*\) .*/\1/p' "$work/stats_after.txt")
  ((failures >= 2)) || fail "auth_failures=$failures, expected >= 2"
  echo "map digest unchanged, 2 robots, auth_failures=$failures"
}

# Per robot, over the frames with a timed pipeline (frames.csv total_ms > 0: not the first):
# their count, Hz = 1000 / mean total_ms (frames run back to back), mean fetch and integrate ms.
report_rates() {
  local car
  for car in car1 car2; do
    awk -F, -v car="$car" -v loss="$loss" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
      $col["total_ms"] > 0 { n++; f += $col["fetch_ms"]; g += $col["integrate_ms"]; t += $col["total_ms"] }
      END { printf "%s,%s,%d,%.1f,%.1f,%.1f\n", loss, car, n, 1000 * n / t, f / n, g / n }' \
      "$work/$car/frames.csv"
  done | tee -a "${csv:-/dev/null}" | sed 's/^/  loss,robot,frames,Hz,fetch_ms,integrate_ms: /'
}

make_lan
start_server
robots_map_together
check_stats_from_robot_host
report_rates
intruder_is_refused
keep_work=$keep
echo "PASS: fleet (2 robots on 2 hosts, intruder refused, loss $loss %)"
