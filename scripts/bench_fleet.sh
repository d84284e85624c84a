#!/usr/bin/env bash
# Fleet benchmark (issue 14): tests/integration/fleet_test.sh (map_server and R robots, each on
# its own network-namespace host, LAN mode, intruder refused) at several packet loss rates on
# the robot links, with more frames than CI; prints one markdown table (docs/fleet.md) with each
# robot's rate and its fetch (GET_CHUNK) and integrate latency percentiles. Every run must pass
# (each scan integrated exactly once, chunks arriving); no rate is judged.
#
# Usage: scripts/bench_fleet.sh [--build DIR] [--robots "2"] [--frames N] [--loss "0 1 5"]
#                              [--timeout-ms MS]     (as root)
#   --robots takes a list too ("2 8"): every robot count runs at every loss rate.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=$root/build counts=2 frames=20 rates="0 1 5" timeout_ms=500
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --robots) counts=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --loss) rates=$2; shift 2 ;;
    --timeout-ms) timeout_ms=$2; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench_fleet: unknown argument $1" >&2; exit 2 ;;
  esac
done
csv=$(mktemp)
trap 'rm -f "$csv"' EXIT
for robots in $counts; do
  for loss in $rates; do
    echo "bench_fleet: $robots robots, loss $loss %, $frames frames per robot" >&2
    bash "$root/tests/integration/fleet_test.sh" --server "$build/map_server/map_server" \
      --client "$build/odom_client/odom_client" --cli "$build/tools/socc-cli" \
      --sim "$build/sim/socc-sim" --robots "$robots" --frames "$frames" --loss "$loss" --timeout-ms "$timeout_ms" \
      --csv "$csv" >&2
  done
done
echo "| loss on robot links | robots | robot | frames | Hz (1000 / mean frame ms) | fetch ms mean / p50 / p99 | integrate ms mean / p50 / p99 |"
echo "|---|---|---|---|---|---|---|"
awk -F, '{ printf "| %s %% | %s | %s | %s | %s | %s / %s / %s | %s / %s / %s |\n",
  $1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11 }' "$csv"
