#!/usr/bin/env bash
# scripts/bench_odometry.sh end to end on a few socc-sim frames: real map_server and odom_client
# processes, the report (with the CPU a frame), and --repeat's interleaved runs against a stand-in baseline (it prints
# fps=50) with their medians.
# usage: bench_script_test.sh <source dir> <build dir>
set -euo pipefail
root=$1 build=$2

# shellcheck source=../integration/test_env.sh
source "$(dirname "$0")/test_env.sh"
require_multicast_on_loopback

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$build/sim/socc-sim" --out "$work/seq" --frames 8 --seed 3 --quiet
SOCC_LCM_URL=$(random_lcm_url 30000) bash "$root/scripts/bench_odometry.sh" "$work/seq" \
  --build "$build" --out "$work/out" --baseline "echo fps=50" --repeat 2 --no-targets \
  >"$work/report.txt" 2>"$work/log.txt" || { cat "$work/log.txt"; fail "bench_odometry.sh failed"; }
cat "$work/report.txt"

[ "$(wc -l <"$work/out/rates.txt")" -eq 2 ] || fail "rates.txt should hold 2 runs"
awk 'NF != 2 || $1 <= 0 || $2 != 50 { exit 1 }' "$work/out/rates.txt" ||
  fail "each run needs socc's rate and the baseline's fps: $(cat "$work/out/rates.txt")"
grep -q "median of 2 runs" "$work/report.txt" || fail "the rate row does not give the median"
grep -q "(median of 2 pairs) -> " "$work/report.txt" || fail "the ratio is not the pairs' median"
[ -s "$work/out/run_2/frames.csv" ] || fail "the second run left no frames.csv"
grep -Eq "CPU a frame: client / server \| [0-9.]+ / [0-9.]+ ms" "$work/report.txt" ||
  fail "the report does not give the CPU a frame"
echo "PASS"
