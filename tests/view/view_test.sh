#!/usr/bin/env bash
# socc-view end to end, in a real browser: a real map_server and two odom_client robots on a
# short socc-sim street (LCM multicast on loopback, random group, ttl=0), socc-view on a free
# port of 127.0.0.1. While the robots run, headless Chromium loads the page (browser_check.cjs:
# map voxels and both robots in the page's state and in the screenshot's pixels; the screenshot
# is kept) and a Foxglove protocol client subscribes to every channel and decodes them
# (foxglove_check.cjs). Then a wrong or missing token is refused when a key is set.
#
# Usage: view_test.sh --server BIN --client BIN --sim BIN --view BIN --node-modules DIR
#                     --screenshot PNG [--frames N]
set -euo pipefail
usage() { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }
server_bin="" client_bin="" sim_bin="" view_bin="" node_modules="" screenshot="" frames=10
while [ $# -gt 0 ]; do
  case "$1" in
    --server) server_bin=$2; shift 2 ;;
    --client) client_bin=$2; shift 2 ;;
    --sim) sim_bin=$2; shift 2 ;;
    --view) view_bin=$2; shift 2 ;;
    --node-modules) node_modules=$2; shift 2 ;;
    --screenshot) screenshot=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "view_test: unknown argument $1" >&2; usage 2 ;;
  esac
done
for b in "$server_bin" "$client_bin" "$sim_bin" "$view_bin"; do
  [[ -x $b ]] || { echo "FAIL: binary '$b' missing"; exit 2; }
done
[[ -d $node_modules/playwright-core ]] || { echo "FAIL: no playwright-core in '$node_modules'"; exit 2; }
[[ -x /usr/bin/chromium ]] || { echo "FAIL: /usr/bin/chromium missing (Debian package chromium)"; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../integration/test_env.sh
source "$here/../integration/test_env.sh"
require_multicast_on_loopback

make_work_dir
keep_work=1
fail() { echo "FAIL: $*"; exit 1; }
url=$(random_lcm_url 40000)
export NODE_PATH=$node_modules

"$sim_bin" --out "$work/sim" --frames $((2 * frames)) --seed 7 --quiet >/dev/null || fail "socc-sim failed"
"$server_bin" --lcm-url "$url" --quiet --status-period 0.5 --view-period 0.25 >"$work/server.log" 2>&1 &
server_pid=$!
start_view() {  # start_view NAME [socc-view options]: socc-view on a free port; sets view_url
  "$view_bin" --lcm-url "$url" --port 0 --url-file "$work/$1.url" "${@:2}" >"$work/$1.log" 2>&1 &
  view_pid=$!
  for _ in $(seq 100); do
    [[ -s $work/$1.url ]] && break
    kill -0 "$view_pid" 2>/dev/null || fail "socc-view exited: $(cat "$work/$1.log")"
    sleep 0.1
  done
  view_url=$(cat "$work/$1.url")
  [[ -n $view_url ]] || fail "socc-view did not start within 10 s"
}
start_view view
echo "socc-view on $view_url (LCM $url)"
ws_url="ws://${view_url#http://}"
ws_url="${ws_url%/}/foxglove"

node "$here/browser_check.cjs" "$view_url" "$work/screenshot.png" robot0 robot1 --timeout 90 \
  >"$work/browser.log" 2>&1 &
browser_pid=$!
node "$here/foxglove_check.cjs" "$ws_url" robot0 robot1 --timeout 90 >"$work/foxglove.log" 2>&1 &
foxglove_pid=$!

# Robot I drives frames [I*frames, (I+1)*frames) from its GT start pose (as the multirobot test).
client_pids=()
for i in 0 1; do
  first=$((i * frames))
  pose=$(kitti_pose "$work/sim/poses.txt" "$first")
  "$client_bin" --kitti "$work/sim" --first-frame "$first" --last-frame $((first + frames - 1)) \
    --initial-pose "$pose" --lcm-url "$url" --robot-id "robot$i" --out-dir "$work/robot$i" \
    --quiet >"$work/robot$i.log" 2>&1 &
  client_pids+=("$!")
done
for i in 0 1; do
  wait "${client_pids[$i]}" || fail "odom_client robot$i failed: $(tail -5 "$work/robot$i.log")"
done
echo "both robots done"
ok=1
wait "$foxglove_pid" || ok=0
sed 's/^/  foxglove: /' "$work/foxglove.log"
wait "$browser_pid" || ok=0
sed 's/^/  browser: /' "$work/browser.log"
if [[ -f $work/screenshot.png && -n $screenshot ]]; then
  cp "$work/screenshot.png" "$screenshot"
  echo "screenshot kept: $screenshot"
fi
((ok)) || fail "browser or Foxglove check failed"
kill "$view_pid"; wait "$view_pid" || true

# LAN safety: with a key, the page and the WebSocket need the token derived from it.
umask 077
openssl rand -hex 32 >"$work/map.key"
"$view_bin" --lcm-url "$url" --bind 0.0.0.0 --port 0 >"$work/nokey.log" 2>&1 &&
  fail "socc-view bound to 0.0.0.0 without --key-file"
grep -q "needs --key-file" "$work/nokey.log" || fail "no reason given: $(cat "$work/nokey.log")"
start_view keyed --key-file "$work/map.key"
[[ $view_url == *"?token="* ]] || fail "keyed socc-view printed no token: $view_url"
base=${view_url%%\?*}
code=$(curl -s -o /dev/null -w '%{http_code}' "$base") || true
[[ $code == 403 ]] || fail "page without token answered $code, not 403"
code=$(curl -s -o /dev/null -w '%{http_code}' "${base}?token=0000") || true
[[ $code == 403 ]] || fail "page with a wrong token answered $code, not 403"
code=$(curl -s -o /dev/null -w '%{http_code}' "$view_url") || true
[[ $code == 200 ]] || fail "page with the token answered $code, not 200"
echo "token: refused without (403), refused wrong (403), served with it (200)"
kill "$view_pid"; wait "$view_pid" || true
kill "$server_pid"; wait "$server_pid" || true
keep_work=0
echo "PASS"
