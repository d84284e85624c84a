#!/usr/bin/env bash
# Manual check (not CI) that lcm-spy decodes socc messages, headless under Xvfb:
#   scripts/check_spy.sh [-b BUILD_DIR] [-o SCREENSHOT.png]
# Starts Xvfb and scripts/spy.sh on a random local multicast port, replays a small generated
# scan log (socc-to-lcmlog + lcm-logplayer), takes a screenshot (xwd -> PNG) and checks that
# lcm-spy loaded the socc types from socc_lcmtypes.jar. Needs: xvfb x11-apps imagemagick
# (apt-get install), a socc build with socc-to-lcmlog. Exit 0 when the types were found.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SOCC_BUILD_DIR:-$root/build}"
png="${TMPDIR:-/tmp}/socc_spy_check.png"
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) sed -n '2,7p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -b | --build) build="$(realpath -m "$2")"; shift 2 ;;
    -o | --output) png="$2"; shift 2 ;;
    *) echo "check_spy.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
for tool in Xvfb xwd convert lcm-logplayer python3; do
  command -v "$tool" >/dev/null || { echo "check_spy.sh: $tool missing (apt-get install xvfb x11-apps imagemagick liblcm-bin)" >&2; exit 1; }
done
to_lcmlog="$build/tools/socc-to-lcmlog"
[ -x "$to_lcmlog" ] || { echo "check_spy.sh: $to_lcmlog not built" >&2; exit 1; }

work="$(mktemp -d)"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# A random port in 50000-59999 so concurrent runs on this machine never see each other.
url="udpm://239.255.76.67:$((50000 + RANDOM % 10000))?ttl=0"
echo "check_spy.sh: LCM URL $url"

Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp 3>"$work/display" 2>"$work/xvfb.log" &
pids+=($!)
for _ in $(seq 50); do [ -s "$work/display" ] && break; sleep 0.1; done
[ -s "$work/display" ] || { echo "check_spy.sh: Xvfb did not start" >&2; cat "$work/xvfb.log" >&2; exit 1; }
export DISPLAY=":$(head -1 "$work/display")"

SOCC_BUILD_DIR="$build" "$root/scripts/spy.sh" "$url" >"$work/spy.log" 2>&1 &
pids+=($!)

# Three small labelled scans (KITTI layout), written as an LCM log of socc.scan_t.
python3 - "$work/seq" <<'PY'
import math, os, struct, sys
root = sys.argv[1]
for d in ("velodyne", "labels"):
    os.makedirs(os.path.join(root, d), exist_ok=True)
for f in range(3):
    pts = [(10 * math.cos(a / 100), 10 * math.sin(a / 100), -1.5 + f, 0.5) for a in range(628)]
    with open(os.path.join(root, "velodyne", "%06d.bin" % f), "wb") as out:
        out.write(b"".join(struct.pack("<4f", *p) for p in pts))
    with open(os.path.join(root, "labels", "%06d.label" % f), "wb") as out:
        out.write(b"".join(struct.pack("<I", 40 if i % 2 else 50) for i in range(len(pts))))
PY
"$to_lcmlog" "$work/seq" -o "$work/scans.lcmlog" --robot-id spy_check -q

# Give the JVM time to start and scan the classpath, then publish for a while.
spy_pid="${pids[-1]}"
for _ in $(seq 100); do
  grep -q "Found [0-9]* LCM types" "$work/spy.log" && break
  kill -0 "$spy_pid" 2>/dev/null || { echo "check_spy.sh: lcm-spy exited:" >&2; cat "$work/spy.log" >&2; exit 1; }
  sleep 0.2
done
for _ in 1 2 3 4 5; do lcm-logplayer --lcm-url="$url" "$work/scans.lcmlog" >/dev/null 2>&1; done
sleep 1
xwd -root -silent -display "$DISPLAY" -out "$work/screen.xwd"
convert "xwd:$work/screen.xwd" "png:$png"
echo "check_spy.sh: screenshot $png"

echo "check_spy.sh: lcm-spy output:"
sed 's/^/  /' "$work/spy.log" | head -40
# lcm-spy 1.3 only prints how many types it found ("Found 20 LCM types"); lcm's own class
# discoverer, run on the same CLASSPATH, names them.
expected="$(ls "$root"/lcmtypes/*.lcm | wc -l)"
found="$(sed -n 's/^Found \([0-9]*\) LCM types.*/\1/p' "$work/spy.log" | head -1)"
if [ "${found:-0}" -lt "$expected" ]; then
  echo "check_spy.sh: FAILED: lcm-spy found ${found:-no} LCM types, expected $expected" >&2
  exit 1
fi
CLASSPATH="/usr/share/java/lcm.jar:$build/lcmtypes/socc_lcmtypes.jar" \
  java lcm.util.ClassDiscoverer 2>/dev/null | grep -o "class socc\.[a-z0-9_]*" | sort >"$work/types"
for t in scan_t integrate_request_t chunk_request_t map_stats_t; do
  grep -qx "class socc.$t" "$work/types" || { echo "check_spy.sh: FAILED: socc.$t not on the classpath" >&2; exit 1; }
  echo "  Found socc.$t"
done
echo "check_spy.sh: OK: lcm-spy loaded $found socc types; look at $png (Type column: scan_t)"
