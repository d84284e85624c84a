#!/usr/bin/env bash
# Load test of map_server: starts it on a random 239.255.76.67 port (ttl=0, large receive
# buffer), runs socc-loadtest with 1, 2, 4 and 8 robots and reports where it saturates: the
# first robot count whose achieved rate drops below 95 % of the target or that loses
# integrations. Results: docs/load.md.
# usage: scripts/load_test.sh [build dir (default build)] [seconds per run (default 15)]
#        env: RATE (default 10), ROBOTS ("1 2 4 8"), KITTI (scan dir; default
#        ../shared/data/kitti_00_first16 when present, else synthetic scans)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=${1:-$root/build}
duration=${2:-15}
rate=${RATE:-10}
robot_counts=${ROBOTS:-"1 2 4 8"}
kitti=${KITTI:-$root/../shared/data/kitti_00_first16}
server_bin=$build/map_server/map_server
load_bin=$build/tools/socc-loadtest
for b in "$server_bin" "$load_bin"; do
  [[ -x $b ]] || { echo "load_test: $b missing (build map_server and socc-loadtest)"; exit 2; }
done
ip route show 224.0.0.0/4 2>/dev/null | grep -q "dev lo" ||
  { echo "load_test: multicast is not routed to lo (scripts/setup.sh)"; exit 2; }

work=$(mktemp -d)
server_pid=""
cleanup() {
  if [[ -n $server_pid ]]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

url="udpm://239.255.76.67:$((20000 + RANDOM % 40001))?ttl=0&recv_buf_size=67108864"
scan_args=()
[[ -d $kitti/velodyne ]] && scan_args=(--kitti "$kitti")
echo "load_test: $url, ${duration} s per run at $rate Hz, scans: ${scan_args[*]:-synthetic}"
"$server_bin" --lcm-url "$url" --file-dir "$work" --quiet >"$work/server.log" 2>&1 &
server_pid=$!

saturated=""
for n in $robot_counts; do
  # One server for all runs (socc-loadtest uses fresh client ids per run); exit code 1 only
  # means lost integrations, which the summary line reports.
  "$load_bin" --lcm-url "$url" --robots "$n" --rate "$rate" --duration "$duration" \
    "${scan_args[@]}" --no-progress >"$work/run_$n.md" 2>"$work/run_$n.err" || true
  cat "$work/run_$n.md"
  kill -0 "$server_pid" 2>/dev/null || { echo "load_test: map_server died"; cat "$work/server.log"; exit 1; }
  summary=$(grep '^summary:' "$work/run_$n.md") || { cat "$work/run_$n.err"; exit 1; }
  pct=$(sed -E 's/.*min_achieved_pct=([0-9.]+).*/\1/' <<<"$summary")
  lost=$(sed -E 's/.*lost=([0-9]+).*/\1/' <<<"$summary")
  if [[ -z $saturated ]] && { [[ $lost != 0 ]] || awk -v p="$pct" 'BEGIN { exit !(p < 95) }'; }; then
    saturated=$n
  fi
done

echo
if [[ -n $saturated ]]; then
  echo "load_test: saturates at $saturated robot(s) ($rate Hz target): achieved < 95 % or lost integrations"
else
  echo "load_test: no saturation up to ${robot_counts##* } robot(s) at $rate Hz"
fi
