#!/usr/bin/env bash
# Consistency benchmark (docs/consistency.md): starts a map_server with the consistency service
# (--consistency-dir), runs odom_client on a KITTI-layout directory with poses.txt (LiDAR frame,
# line = frame), stops the server (which then writes its keyframes, closures and figures) and
# scores them with bench_consistency_eval: map-frame ATE of the keyframes as the odometry
# integrated them (odometry alone: the service does not change what the client does) and as
# the pose graph corrected them, revisits mapped twice, wrong closures, the time to correct a
# loop and the keyframes' memory per km. With map correction the client's own output follows
# the corrected grid: a first run without the service (odometry alone) and the run with it are
# both scored on every pose the client output (map-frame ATE, no alignment); --no-alone skips
# the first run. The output as the pose graph revised it at the end of the run
# (poses_revised_tum.txt, docs/consistency.md "The revised trajectory"; the client waits up to
# 900 s for the service to process its last keyframes) gets a row too. Prints ONE markdown table whose last line sums it up; exit 1 when a target is
# missed (wrong closures > 0, ATE not >= --min-gain (5) times lower: the client output's when
# both runs are there, else the keyframes', any revisit still mapped twice), 0 with
# --no-targets.
#
# --client-config FILE: odom_client's --config (both runs), e.g. odom_client/config/kitti.yaml,
# the simulated HDL-64's vertical-angle correction, for a --realism kitti sequence.
#
# --rate R: the clients replay the sequence at R times its pace (times.txt), 1 by default: as the
# robot drove, so that the service works beside it as on a robot (its time to correct a loop,
# its backlog); 0: as fast as the odometry goes (a 10 Hz HDL-64 drive at about 2.5x on 2 cores,
# which leaves the service that much further behind the drive). At the drive's pace a run takes
# at least the drive's duration: the full 4541-frame KITTI-00 shape 7.6 min per client run.
#
# --robots 2: two clients at the same time, each on half of the frames: robot 1 from the
# sequence's start (its GT frame), robot 2 from the middle with --own-frame and no initial pose
# (maps in its own frame until it enters robot 1's map, docs/relocalization.md "Own frame"; its
# searches: relocalize_timeout 1 s, then one per own_frame_search_period 2 s of scans). Both
# robots' map-frame poses are scored together; robot 2 never merged (exit 5) is reported and
# only robot 1's poses are scored.
#
# --server-config FILE: map_server's --config (both runs) instead of
# bench/config/server_unthrottled.yaml, e.g. with `consistency: {rebuild_region: false}` to
# time whole-map rebuilds against region rebuilds (docs/consistency.md "Region rebuilds").
#
# Usage: scripts/bench_consistency.sh SEQ_DIR [--build BUILD] [--out OUT] [--frames N]
#                                     [--first-frame N] [--min-gain G] [--no-targets]
#                                     [--no-alone] [--client-config FILE] [--robots 1|2]
#                                     [--rate R] [--server-config FILE]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { sed -n '2,41p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

[ $# -ge 1 ] || usage 2
case "$1" in -h|--help) usage 0 ;; esac
[ -d "$1" ] || { echo "bench_consistency: $1 is not a directory" >&2; exit 2; }
dir="$(cd "$1" && pwd)"; shift
build="$root/build"; out=""; client_args=(); eval_args=(); judge=1; alone=1; robots=1
first=0; frames=0; rate=1; server_config="$root/bench/config/server_unthrottled.yaml"
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --first-frame) first=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    --min-gain) eval_args+=(--min-gain "$2"); shift 2 ;;
    --no-targets) judge=0; shift ;;
    --no-alone) alone=0; shift ;;
    --client-config) client_args+=(--config "$2"); shift 2 ;;
    --rate) rate=$2; shift 2 ;;
    --server-config) server_config=$2; shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "bench_consistency: unknown argument $1" >&2; usage 2 ;;
  esac
done
[[ $rate == 0 ]] || client_args+=(--rate "$rate")
[ -f "$dir/poses.txt" ] || { echo "bench_consistency: $dir/poses.txt missing" >&2; exit 2; }
[[ $robots == 1 || $robots == 2 ]] || { echo "bench_consistency: --robots must be 1 or 2" >&2; exit 2; }
total=$(find "$dir/velodyne" -name '*.bin' | wc -l)
last=$((frames > 0 ? frames - 1 : total - 1))
middle=$(((first + last + 1) / 2))
out="${out:-$root/out/bench_consistency_$(basename "$dir")}"
mkdir -p "$out"
for bin in map_server/map_server odom_client/odom_client tools/socc-cli bench/bench_consistency_eval; do
  [ -x "$build/$bin" ] || { echo "bench_consistency: $build/$bin missing: build it" >&2; exit 2; }
done

# Private multicast port so concurrent runs never see each other; ttl=0 keeps it on this machine.
server=""
trap '[ -z "$server" ] || kill "$server" 2>/dev/null || true' EXIT
# client DIR ROBOT URL [odom_client args...]: one odom_client into DIR (exit 0 or 3 accepted).
client() {
  local to=$1 robot=$2 url=$3 rc=0; shift 3
  mkdir -p "$to"
  "$build/odom_client/odom_client" --kitti "$dir" --lcm-url "$url" --robot-id "$robot" \
    --out-dir "$to" --revised-wait 900 "${client_args[@]}" "$@" >"$to/client_summary.txt" \
    2>"$to/client.log" || rc=$?
  [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || [ "$rc" -eq 5 ] ||
    { echo "bench_consistency: odom_client failed ($rc), see $to/client.log" >&2; exit 1; }
  echo "$rc" >"$to/exit_code"
}
# run_two DIR URL: robot 1 on the first half, robot 2 (--own-frame) on the second, at once; both
# robots' map-frame poses into DIR/poses_tum.txt.
run_two() {
  local to=$1 url=$2 pid1 pid2
  printf 'relocalize_timeout: 1.0\nown_frame_search_period: 2.0\n' >"$out/own_frame.yaml"
  client "$to/robot1" bench "$url" --first-frame "$first" --last-frame "$((middle - 1))" &
  pid1=$!
  client "$to/robot2" bench2 "$url" --first-frame "$middle" --last-frame "$last" --own-frame \
    --config "$out/own_frame.yaml" &
  pid2=$!
  wait "$pid1" || exit 1
  wait "$pid2" || exit 1
  grep -h "found the shared map\|merged into\|input ended" "$to/robot2/client.log" >&2 || true
  { cat "$to/robot1/poses_tum.txt"; cat "$to/robot2/poses_tum.txt" 2>/dev/null || true; } |
    sort -n >"$to/poses_tum.txt"
  if [ -f "$to/robot1/poses_revised_tum.txt" ]; then
    { cat "$to/robot1/poses_revised_tum.txt"; cat "$to/robot2/poses_revised_tum.txt" 2>/dev/null ||
      true; } | sort -n >"$to/poses_revised_tum.txt"
  fi
}
# run NAME [server args...]: one map_server + the odom_client(s) into $out/NAME.
run() {
  local name="$1"; shift
  local url="udpm://239.255.76.67:$((20000 + RANDOM % 40000))?ttl=0&recv_buf_size=33554432"
  mkdir -p "$out/$name"
  "$build/map_server/map_server" --lcm-url "$url" --quiet \
    --config "$server_config" "$@" >"$out/$name/server.log" 2>&1 &
  server=$!
  for _ in $(seq 50); do
    "$build/tools/socc-cli" --lcm-url "$url" --client-id bench stats >/dev/null 2>&1 && break
    sleep 0.2
  done
  echo "bench_consistency: odom_client on $dir ($name, $robots robot(s))" >&2
  if [ "$robots" -eq 1 ]; then
    client "$out/$name" bench "$url" --first-frame "$first" --last-frame "$last"
  else
    run_two "$out/$name" "$url"
  fi
  # A clean stop: the server finishes the keyframes it holds, then writes what it was asked to.
  kill -TERM "$server"
  wait "$server" || { echo "bench_consistency: map_server failed, see $out/$name/server.log" >&2
                      exit 1; }
  server=""
}

rm -rf "$out/consistency"
if [ "$alone" -eq 1 ]; then
  run alone
  eval_args+=(--alone-tum "$out/alone/poses_tum.txt")
fi
run with --consistency-dir "$out/consistency"
trap - EXIT
[ -f "$out/consistency/stats.txt" ] || { echo "bench_consistency: no consistency output" >&2; exit 1; }
[ -f "$dir/times.txt" ] &&
  eval_args+=(--client-tum "$out/with/poses_tum.txt" --times "$dir/times.txt")
# The client's output revised by the pose graph at the end of its run (odom_client asks the
# server for its keyframes; nothing is written when it has none).
[ -f "$dir/times.txt" ] && [ -f "$out/with/poses_revised_tum.txt" ] &&
  eval_args+=(--revised-tum "$out/with/poses_revised_tum.txt")

rc=0
"$build/bench/bench_consistency_eval" --dir "$out/consistency" --gt "$dir/poses.txt" \
  "${eval_args[@]}" | tee "$out/table.md" || rc=$?
[ "$rc" -le 1 ] || exit 1
[ "$judge" -eq 1 ] && exit "$rc"
exit 0
