#!/usr/bin/env bash
# Fleet test (issue 14): map_server and two robots on separate hosts of one LAN, in network
# namespaces this test creates (fleet_netns.sh: hosts server, robot1..robotR, intruder joined by
# a bridge inside a namespace; nothing touches a real interface) and deletes at the end, also
# on failure. LCM runs in LAN mode: udpm://239.255.x.y:port?ttl=1 with a shared key.
#
# Usage: fleet_test.sh --server BIN --client BIN --cli BIN --sim BIN [--robots R] [--frames N]
#                      [--loss PCT] [--timeout-ms MS] [--csv FILE] [--keep]
#   R robots (default 2), each on its own host, drive consecutive N-frame segments (default 4)
#   of one socc-sim street (HDL-64: KITTI-size scans, 1.6 MB per INTEGRATE) from their GT start
#   poses, at the same time, as fast as they can.
#   Checks: every robot exits 0 with N poses; `socc-cli stats` run on robot2's host lists all R
#   robots, each with its last seq and exactly N integrations (each scan applied once); an
#   intruder host without the key cannot even open the LAN URL, and with a wrong key gets
#   UNAUTHENTICATED for socc-cli and odom_client; afterwards the map digest is unchanged,
#   the intruder is not listed and auth_failures counts its requests.
#   --loss PCT drops PCT % of the IP packets (each fragment alone) in and out of each robot
#   host (nftables); --csv appends one line per robot: loss, robots, robot, frames, Hz, fetch ms
#   mean/p50/p99, integrate ms mean/p50/p99.
#   --timeout-ms: odom_client's per-attempt timeout (default 500; 20 attempts).
#   --keep keeps the work directory (logs, frames.csv of each robot) also when the test passes.
# Needs root (CAP_NET_ADMIN) and nft for --loss; without them it FAILS (it never skips).
set -euo pipefail
usage() { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

server_bin="" client_bin="" cli_bin="" sim_bin="" robots=2 frames=4 loss=0 timeout_ms=500 csv="" keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --server) server_bin=$2; shift 2 ;;
    --client) client_bin=$2; shift 2 ;;
    --cli) cli_bin=$2; shift 2 ;;
    --sim) sim_bin=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --loss) loss=$2; shift 2 ;;
    --timeout-ms) timeout_ms=$2; shift 2 ;;
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
# shellcheck source=test_env.sh
source "$here/test_env.sh"  # kitti_pose

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

((robots >= 2)) || { echo "FAIL: --robots must be at least 2"; exit 2; }
robot_hosts=()
for ((i = 1; i <= robots; i++)); do robot_hosts+=("robot$i"); done

make_lan() {
  if ! netns_lan_create "$prefix" server "${robot_hosts[@]}" intruder 2>"$work/netns.log"; then
    fail "cannot create network namespaces (needs root / CAP_NET_ADMIN): $(cat "$work/netns.log")"
  fi
  if [[ $loss != 0 ]]; then
    command -v nft >/dev/null || fail "--loss needs nft (Debian package nftables)"
    local host
    for host in "${robot_hosts[@]}"; do
      netns_lan_loss "$prefix" "$host" "$loss" || fail "cannot install the nftables loss rules"
    done
  fi
  echo "LAN: namespaces $prefix-{lan,server,robot1..robot$robots,intruder}, $url, loss $loss % on robot links"
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

gt_pose() { kitti_pose "$work/sim/poses.txt" "$1"; }  # gt_pose FRAME (test_env.sh)

# On a lossy LAN a lost small request or reply (one packet) costs one attempt's timeout: 500 ms
# instead of the default 2 s (docs/fleet.md), with attempts enough for several losses in a row.
printf 'timeout_ms: %d\nmax_attempts: 20\n' "$timeout_ms" >"$work/lan.yaml"

run_robot() {  # run_robot HOST ROBOT_ID FIRST KEY: odom_client on frames FIRST.. on HOST
  in_host "$prefix" "$1" "$client_bin" --kitti "$work/sim" --config "$work/lan.yaml" --first-frame "$3" \
    --last-frame $(($3 + frames - 1)) --initial-pose "$(gt_pose "$3")" --lcm-url "$url" \
    --key-file "$4" --robot-id "$2" --out-dir "$work/$2" --quiet >"$work/$2.log" 2>&1
}

# Robot i (car<i>) runs on host robot<i> on frames [(i-1)*N, i*N-1].
robots_map_together() {
  "$sim_bin" --out "$work/sim" --frames $((robots * frames)) --seed 7 --quiet >/dev/null ||
    fail "socc-sim failed"
  local start=$SECONDS i pids=()
  for ((i = 1; i <= robots; i++)); do
    run_robot "robot$i" "car$i" $(((i - 1) * frames)) "$key" &
    pids+=("$!")
  done
  for ((i = 1; i <= robots; i++)); do
    wait "${pids[$((i - 1))]}" || fail "car$i (robot$i host) failed: $(tail -5 "$work/car$i.log")"
    [[ $(wc -l <"$work/car$i/poses_kitti.txt") == "$frames" ]] || fail "car$i wrote no $frames poses"
  done
  echo "$robots robots on $robots hosts: $frames frames each in $((SECONDS - start)) s"
}

check_stats_from_robot_host() {
  cli_on robot2 stats | tee "$work/stats.txt" | sed 's/^/  stats (robot2 host): /'
  grep -q " robots=$robots$" "$work/stats.txt" ||
    fail "GET_STATS from robot2's host does not list $robots robots"
  local i last
  for ((i = 1; i <= robots; i++)); do
    last=$((i * frames - 1))
    grep -q "^car$i seq=$last integrations=$frames " "$work/stats.txt" ||
      fail "car$i: expected last seq $last and $frames integrations (each scan once)"
  done
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
  grep -q " robots=$robots$" "$work/stats_after.txt" || fail "robots changed after the intruder"
  grep -q "^intruder " "$work/stats_after.txt" && fail "the intruder is listed as a robot"
  local failures
  failures=$(sed -n '1s/.* auth_failures=\([0-9]*\) .*/\1/p' "$work/stats_after.txt")
  ((failures >= 2)) || fail "auth_failures=$failures, expected >= 2"
  echo "map digest unchanged, $robots robots, auth_failures=$failures"
}

# column_stats CSV COLUMN: "mean,p50,p99" (nearest rank) of COLUMN of a frames.csv over the
# frames with a timed pipeline (total_ms > 0).
column_stats() {
  awk -F, -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    $col["total_ms"] > 0 { print $col[c] }' "$1" | sort -g |
    awk 'function rank(p,  r) { r = int(p * NR); if (r < p * NR) r++; return r < 1 ? 1 : r }
      { v[NR] = $1; s += $1 }
      END { printf "%.1f,%.1f,%.1f", s / NR, v[rank(0.5)], v[rank(0.99)] }'
}

# Per robot: frames, Hz = 1000 / mean total_ms (frames run back to back), fetch and integrate
# ms (mean, p50, p99).
report_rates() {
  local i csv_file frames_done total
  for ((i = 1; i <= robots; i++)); do
    csv_file=$work/car$i/frames.csv
    frames_done=$(awk -F, 'NR > 1' "$csv_file" | wc -l)
    total=$(column_stats "$csv_file" total_ms)
    echo "$loss,$robots,car$i,$frames_done,$(awk -v t="${total%%,*}" 'BEGIN { printf "%.1f", 1000 / t }'),$(column_stats "$csv_file" fetch_ms),$(column_stats "$csv_file" integrate_ms)"
  done | tee -a "${csv:-/dev/null}" |
    sed 's/^/  loss,robots,robot,frames,Hz,fetch mean,p50,p99,integrate mean,p50,p99: /'
}

make_lan
start_server
robots_map_together
check_stats_from_robot_host
report_rates
intruder_is_refused
keep_work=$keep
echo "PASS: fleet ($robots robots on $robots hosts, intruder refused, loss $loss %)"
