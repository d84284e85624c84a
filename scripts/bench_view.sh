#!/usr/bin/env bash
# socc-view's costs (issue 31): R robots (odom_client on a socc-sim street, one segment each,
# replaying as fast as they can) against a real map_server with the view stream on
# (--view-period, default 0.5 s), socc-view, one page client reading everything
# (tests/view/page_client.cjs: what a browser receives) and one stalled client that reads
# nothing (a hung tab). Per robot count it prints a markdown row. Costs are per integrated scan
# (x 10 = per second of a 10 Hz robot): SOCC/MAP_DELTA bytes, the bytes the page client got,
# socc-view's CPU; and the map server's CPU, socc-view's memory. Exits 1 when a target is missed:
#   MAP_DELTA <= 40 KiB per scan         to the page <= 30 KiB per scan
#   socc-view CPU <= 5 ms per scan (5 % of a core for a 10 Hz robot)
#   the stalled client delays nobody: the page client got at least 90 % of what a page loading
#   the finished map gets, and socc-view's RSS stays <= 300 MiB
#
# --page-voxels N: then the page's level of detail on a synthetic map of N voxels
# (bench/view/page_lod.cjs: a stand-in bridge, headless Chromium; target: at most 1.5 M points
# drawn from the overview camera).
#
# Usage: scripts/bench_view.sh [--build DIR] [--robots "1 2"] [--frames N] [--view-period S]
#                              [--page-voxels N]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=$root/build counts="1 2" frames=30 view_period=0.5 page_voxels=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --robots) counts=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --view-period) view_period=$2; shift 2 ;;
    --page-voxels) page_voxels=$2; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench_view: unknown argument $1" >&2; exit 2 ;;
  esac
done
server_bin=$build/map_server/map_server client_bin=$build/odom_client/odom_client
sim_bin=$build/sim/socc-sim view_bin=$build/tools/socc-view
for b in "$server_bin" "$client_bin" "$sim_bin" "$view_bin"; do
  [[ -x $b ]] || { echo "bench_view: $b missing (ninja -C $build map_server odom_client socc-sim socc-view)" >&2; exit 2; }
done
export NODE_PATH=$build/tools/view/node/node_modules
# shellcheck source=../tests/integration/test_env.sh
source "$root/tests/integration/test_env.sh"
require_multicast_on_loopback

make_work_dir

ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }  # utime + stime of a process [clock ticks]
hz=$(getconf CLK_TCK)
max_robots=0
for r in $counts; do ((r > max_robots)) && max_robots=$r; done
if ((max_robots > 0)); then
  echo "bench_view: socc-sim, $((max_robots * frames)) frames" >&2
  "$sim_bin" --out "$work/sim" --frames $((max_robots * frames)) --seed 7 --quiet >/dev/null
fi

metric() { sed -n "s/.*\"$2\":\([0-9]*\).*/\1/p" <<<"$1"; }
missed=0
rows=()
for robots in $counts; do
  echo "bench_view: $robots robots x $frames frames" >&2
  url=$(random_lcm_url 40000)
  "$server_bin" --lcm-url "$url" --quiet --view-period "$view_period" >"$work/server.log" 2>&1 &
  server_pid=$!
  rm -f "$work/url"
  "$view_bin" --lcm-url "$url" --port 0 --url-file "$work/url" >"$work/view.log" 2>&1 &
  view_pid=$!
  for _ in $(seq 100); do [[ -s $work/url ]] && break; sleep 0.1; done
  page_url=$(cat "$work/url")
  ws_url="ws://${page_url#http://}"
  ws_url="${ws_url%/}/ws"
  node "$root/tests/view/page_client.cjs" "$ws_url" >"$work/page.json" &
  page_pid=$!
  node "$root/tests/view/page_client.cjs" "$ws_url" --stall >"$work/stalled.log" 2>&1 &
  stalled_pid=$!
  sleep 1
  view_ticks0=$(ticks "$view_pid") server_ticks0=$(ticks "$server_pid")
  start=$(date +%s.%N)
  pids=()
  for ((i = 0; i < robots; i++)); do
    first=$((i * frames))
    pose=$(kitti_pose "$work/sim/poses.txt" "$first")
    "$client_bin" --kitti "$work/sim" --first-frame "$first" --last-frame $((first + frames - 1)) \
      --initial-pose "$pose" --lcm-url "$url" --robot-id "robot$i" --out-dir "$work/robot$i" \
      --quiet >"$work/robot$i.log" 2>&1 &
    pids+=("$!")
  done
  for p in "${pids[@]}"; do wait "$p"; done
  end=$(date +%s.%N)
  sleep $(awk -v p="$view_period" 'BEGIN { print 4 * p + 1 }')  # the last blocks reach the page
  view_ticks1=$(ticks "$view_pid") server_ticks1=$(ticks "$server_pid")
  rss_kib=$(awk '/VmRSS/ { print $2 }' "/proc/$view_pid/status")
  metrics=$(curl -s "${page_url%%\?*}metrics.json")
  kill "$page_pid"; wait "$page_pid" || true
  page_bytes=$(sed -n 's/.*"bytes":\([0-9]*\).*/\1/p' "$work/page.json")
  # What a page loading the finished map receives (the reference for "received the final map").
  node "$root/tests/view/page_client.cjs" "$ws_url" >"$work/fresh.json" &
  fresh_pid=$!
  sleep 3
  kill "$fresh_pid"; wait "$fresh_pid" || true
  fresh_bytes=$(sed -n 's/.*"bytes":\([0-9]*\).*/\1/p' "$work/fresh.json")
  for p in stalled view server; do
    pid_var=${p}_pid
    kill -0 "${!pid_var}" 2>/dev/null || echo "bench_view: the $p process ended early: $(cat "$work/$p.log")" >&2
    kill "${!pid_var}" 2>/dev/null || true
    wait "${!pid_var}" 2>/dev/null || true
  done
  delta_bytes=$(metric "$metrics" delta_bytes)
  voxels=$(metric "$metrics" voxels)
  row=$(awk -v r="$robots" -v f="$frames" -v s="$start" -v e="$end" -v d="$delta_bytes" \
    -v pb="$page_bytes" -v fb="$fresh_bytes" -v vt=$((view_ticks1 - view_ticks0)) \
    -v st=$((server_ticks1 - server_ticks0)) -v hz="$hz" -v rss="$rss_kib" -v vox="$voxels" 'BEGIN {
      t = e - s; scans = r * f
      dk = d / 1024 / scans; pk = pb / 1024 / scans; cpu = 1000 * vt / hz / scans
      got = 100 * pb / (fb > 0 ? fb : 1)
      ok = dk <= 40 && pk <= 30 && cpu <= 5 && got >= 90 && rss <= 300 * 1024
      printf "| %d | %d | %.1f | %.1f | %d | %.1f | %.1f | %.2f | %.1f | %.0f %% | %.0f | %s |\n",
        r, scans, t, scans / t, vox, dk, pk, cpu, 1000 * st / hz / scans, got, rss / 1024,
        ok ? "met" : "MISSED"
    }')
  rows+=("$row")
  [[ $row == *MISSED* ]] && missed=1
done
if ((max_robots > 0)); then
  echo "| robots | scans | run s | scans/s | voxels | MAP_DELTA KiB/scan | to page KiB/scan | socc-view CPU ms/scan | map_server CPU ms/scan | page got / fresh load | socc-view RSS MiB | targets |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${rows[@]}"
  echo "targets: MAP_DELTA <= 40 KiB/scan, to page <= 30 KiB/scan, socc-view CPU <= 5 ms/scan, page got >= 90 % of a fresh load despite a stalled client, RSS <= 300 MiB"
fi
if ((page_voxels > 0)); then
  echo "bench_view: the page with $page_voxels voxels" >&2
  node "$root/bench/view/page_lod.cjs" "$build/tools/view/web" --voxels "$page_voxels" || missed=1
fi
exit "$missed"
