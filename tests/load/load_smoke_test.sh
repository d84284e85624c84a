#!/usr/bin/env bash
# Smoke test of socc-loadtest against a real map_server: 2 robots, 2 Hz, 3 s, small synthetic
# scans; asserts that every integration was acknowledged and applied.
# usage: load_smoke_test.sh <map_server> <socc-loadtest>
set -euo pipefail
server_bin=$1 load_bin=$2

# shellcheck source=../integration/test_env.sh
source "$(dirname "$0")/../integration/test_env.sh"
require_multicast_on_loopback

make_work_dir
server_pid=""

url=$(random_lcm_url 40000)
echo "LCM URL: $url   work dir: $work"

fail() { echo "FAIL: $*"; [[ -f $work/server.log ]] && sed 's/^/  server: /' "$work/server.log"; exit 1; }

"$server_bin" --lcm-url "$url" --file-dir "$work" --quiet >"$work/server.log" 2>&1 &
server_pid=$!

# socc-loadtest waits up to 10 s for the server to answer GET_STATS before it starts.
"$load_bin" --lcm-url "$url" --robots 2 --rate 2 --duration 3 --synthetic-points 5000 \
  --no-progress --json "$work/load.json" >"$work/load.md" 2>&1 && rc=0 || rc=$?
cat "$work/load.md"
[[ $rc == 0 ]] || fail "socc-loadtest exited with $rc"
kill -0 "$server_pid" 2>/dev/null || fail "map_server died during the load test"

grep -q '"lost_integrations": 0,' "$work/load.json" || fail "lost integrations"
grep -q '"server_stats_ok": true' "$work/load.json" || fail "GET_STATS at the end failed"
# 2 robots x 2 Hz x 3 s = 6 integrations each (>= 4 on a busy machine), every one applied:
# the server's last seq equals the last one sent.
[[ $(grep -cE '"sent": ([4-9]|[1-9][0-9]+), "unacknowledged": 0, "not_applied": 0, "server_last_seq": ([0-9]+),' \
     "$work/load.json") == 2 ]] || fail "expected >= 4 applied integrations per robot"
grep -E '"sent": ([0-9]+), .*"server_last_seq": ([0-9]+),' "$work/load.json" |
  sed -E 's/.*"sent": ([0-9]+),.*"server_last_seq": ([0-9]+),.*/\1 \2/' |
  while read -r sent last; do [[ $sent == "$last" ]] || fail "sent $sent but server last seq $last"; done
echo "PASS: load smoke"
