#!/usr/bin/env bash
# socc-sim speed against its target (README "Status"): 300 HDL-64 frames of the default urban
# street in under 60 s. Prints wall and CPU time and one markdown row; exits 1 when the wall
# time misses the limit, 2 on a usage or build error. The sequence goes to a temporary
# directory that is removed afterwards.
#
# --realism (default kitti, the benchmarks' preset; none: the exact simulator).
#
# Usage: scripts/bench_sim_speed.sh [--build BUILD] [--frames 300] [--limit-s 60] [--seed 1]
#                                   [--realism kitti|none]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }
build="$root/build"; frames=300; limit=60; seed=1; realism=kitti
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --limit-s) limit="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --realism) realism="$2"; shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "bench_sim_speed: unknown argument $1" >&2; usage 2 ;;
  esac
done
sim="$build/sim/socc-sim"
[ -x "$sim" ] || { echo "bench_sim_speed: $sim missing: run scripts/build.sh" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# bash's time keyword: wall, user and system seconds of socc-sim alone (its stderr is kept apart).
TIMEFORMAT='%R %U %S'
{ time "$sim" --out "$work/seq" --frames "$frames" --seed "$seed" --sensor hdl64 \
    --realism "$realism" --quiet \
    >/dev/null 2>"$work/sim.err"; } 2>"$work/time" || { cat "$work/sim.err" >&2; exit 1; }
read -r wall user sys <"$work/time"
written="$(find "$work/seq/velodyne" -name '*.bin' | wc -l)"
[ "$written" -eq "$frames" ] || { echo "bench_sim_speed: wrote $written of $frames frames" >&2; exit 1; }
load="$(cut -d' ' -f1 /proc/loadavg)"
verdict="$(awk -v w="$wall" -v l="$limit" 'BEGIN {print (w < l) ? "met" : "MISSED"}')"
echo "| socc-sim: $frames HDL-64 frames ($realism) < $limit s | $wall s wall ($(awk -v u="$user" -v s="$sys" \
  'BEGIN {printf "%.1f", u + s}') s CPU), load $load | $verdict |"
[ "$verdict" = met ]
