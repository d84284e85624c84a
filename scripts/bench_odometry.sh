#!/usr/bin/env bash
# Odometry benchmark report: starts a map_server, runs odom_client on a KITTI-layout directory,
# evaluates against DIR/poses.txt (LiDAR frame; or --gt/--calib for KITTI camera-frame GT),
# prints ONE markdown table (accuracy, per-stage timing, CPU a frame, Hz, bytes/frame, server
# memory), and writes trajectory/error plots (PNG) and top-down map images (by class, by
# occupancy) with a legend, a scale bar and both trajectories. --baseline CMD runs another
# odometry on the same data in the same run (`CMD DIR`, must print fps=F; e.g. a KISS-ICP
# runner built outside the repository), side by side, with its poses scored when
# --baseline-poses names the KITTI pose file CMD writes (LiDAR frame). Exit 1 when a target of
# odom_client/README.md "Performance" is missed: end to end >= 1.2x the baseline's fps (35 Hz
# without one), frame time p99 <= 3x the median, chunk traffic <= 300 KiB/frame, Integrate
# upload <= 1 MB/frame (--no-targets: report them, exit 0; for callers that judge accuracy, e.g.
# demo.sh). --repeat N: N runs of socc (a fresh map server each) and of the baseline,
# interleaved; the rates are their medians and the ratio judged is the median of the N pairs'
# (one pair on a shared machine is noise). --baseline-pose-at end|start|auto: peers that deskew
# (KISS-ICP, GenZ-ICP) report each pose at the END of its sweep (the next sweep's start) while
# socc-sim's poses.txt holds the sweep's start: `end` scores them one frame shifted; auto (the
# default) = end when DIR/point_times exists (the peer deskews), else start. --server-config
# YAML: the map_server settings (default bench/config/server_unthrottled.yaml; a grid of other
# parameters through its map_config key).
#
# Usage: scripts/bench_odometry.sh DIR [--build BUILD] [--out OUT] [--gt POSES] [--calib CALIB]
#                                  [--lengths 100,200,...] [--no-semantics] [--no-gravity] [--frames N]
#                                  [--config ODOM_YAML] [--baseline CMD [--baseline-poses FILE]]
#                                  [--baseline-pose-at end|start|auto] [--repeat N] [--no-targets]
#                                  [--server-config SERVER_YAML]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { sed -n '2,26p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

[ $# -ge 1 ] || usage 2
case "$1" in -h|--help) usage 0 ;; esac
dir="$(cd "$1" && pwd)"; shift
build="$root/build"; out=""; gt=""; calib=""; lengths=""; client_args=()
baseline=""; baseline_poses=""; baseline_pose_at=auto; judge=1; repeat=1
server_config="$root/bench/config/server_unthrottled.yaml"
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --gt) gt="$2"; shift 2 ;;
    --calib) calib="$2"; shift 2 ;;
    --lengths) lengths="$2"; shift 2 ;;
    --no-semantics) client_args+=(--no-semantics); shift ;;
    --no-gravity) client_args+=(--no-gravity); shift ;;
    --config) client_args+=(--config "$2"); shift 2 ;;
    --frames) client_args+=(--last-frame "$(($2 - 1))"); shift 2 ;;
    --baseline) baseline="$2"; shift 2 ;;
    --baseline-poses) baseline_poses="$2"; shift 2 ;;
    --baseline-pose-at) baseline_pose_at="$2"; shift 2 ;;
    --no-targets) judge=0; shift ;;
    --server-config) server_config="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "bench_odometry: unknown argument $1" >&2; usage 2 ;;
  esac
done
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "bench_odometry: --repeat needs a count >= 1" >&2; exit 2; }
out="${out:-$root/out/bench_$(basename "$dir")}"
mkdir -p "$out"
gt="${gt:-$dir/poses.txt}"
for bin in map_server/map_server odom_client/odom_client eval/socc-eval tools/socc-cli; do
  [ -x "$build/$bin" ] || { echo "bench_odometry: $build/$bin missing: run scripts/build.sh" >&2; exit 2; }
done

# Private multicast port so concurrent runs never see each other; ttl=0 keeps it on this machine.
private_url() { echo "udpm://239.255.76.67:$((20000 + RANDOM % 40000))?ttl=0&recv_buf_size=33554432"; }
url="${SOCC_LCM_URL:-$(private_url)}"
cli=("$build/tools/socc-cli" --lcm-url "$url" --client-id bench)

# One robot replaying as fast as it can: without the per-robot fairness limits (server.yaml caps
# a robot at 40 INTEGRATEs a second), bench/config/server_unthrottled.yaml.
# start_server URL LOG: a map server on URL, its pid in $started; fails when it does not answer.
start_server() {
  "$build/map_server/map_server" --lcm-url "$1" --quiet \
    --config "$server_config" >"$2" 2>&1 &
  started=$!
  for _ in $(seq 50); do
    "$build/tools/socc-cli" --lcm-url "$1" --client-id bench stats >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  "$build/tools/socc-cli" --lcm-url "$1" --client-id bench stats >/dev/null 2>&1
}
stop_server() { kill "$1" 2>/dev/null || true; wait "$1" 2>/dev/null || true; }
answered=1
start_server "$url" "$out/server.log" || answered=0
server=$started run_server=""
trap 'stop_server "$server"; [ -z "$run_server" ] || stop_server "$run_server"' EXIT
[ "$answered" -eq 1 ] || { echo "bench_odometry: map_server did not answer" >&2; cat "$out/server.log" >&2; exit 1; }

# CPU seconds of the run: the client's from this shell's reaped children (`times` in this
# shell, not a subshell: its second line, user then system), the server's from /proc.
children_cpu() { awk 'NR == 2 { split($0, f, /[ms ]+/); print f[1] * 60 + f[2] + f[3] * 60 + f[4] }' "$1"; }
server_cpu() { awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "/proc/$server/stat"; }
# The sequence read once beforehand: the pipeline is timed, not the disk (a baseline like the
# KISS-ICP runner loads every scan before its clock starts). A cold page cache put reads of
# up to 1.2 s into the first run's frame times on an 800-frame sequence (p99 391 ms against
# 57-67 ms in the warm runs after it).
find "$dir" -type f -exec cat {} + >/dev/null
times >"$out/times_before.txt"
server_cpu0=$(server_cpu)

echo "bench_odometry: odom_client on $dir" >&2
client_rc=0
# --no-revised: this server runs without the consistency service (no revised trajectory to ask).
"$build/odom_client/odom_client" --kitti "$dir" --lcm-url "$url" --robot-id bench \
  --out-dir "$out" --no-revised "${client_args[@]}" | tee "$out/client_summary.txt" >&2 || client_rc=$?
times >"$out/times_after.txt"
awk -v c0="$(children_cpu "$out/times_before.txt")" -v c1="$(children_cpu "$out/times_after.txt")" \
  -v s0="$server_cpu0" -v s1="$(server_cpu)" 'BEGIN { print c1 - c0, s1 - s0 }' >"$out/cpu.txt"
# Exit 3: the robot declared itself lost (its frames.csv says where); still scored below.
[ "$client_rc" -eq 0 ] || [ "$client_rc" -eq 3 ] || { echo "bench_odometry: odom_client failed ($client_rc)" >&2; exit 1; }

eval_args=(--gt "$gt" --est "$out/poses_kitti.txt" --truncate --json "$out/eval.json" --plot-dir "$out/plots")
# KITTI layouts carry calib.txt: GT in the camera frame is converted with its Tr (identity for socc-sim).
[ -z "$calib" ] && [ -f "$dir/calib.txt" ] && calib="$dir/calib.txt"
[ -n "$calib" ] && eval_args+=(--calib "$calib")
[ -n "$lengths" ] && eval_args+=(--lengths "$lengths")
"$build/eval/socc-eval" "${eval_args[@]}" >"$out/eval.txt"

# The baseline on the same scans, after socc's run (not beside it: two cores).
: >"$out/baseline.txt"
if [ -n "$baseline" ]; then
  echo "bench_odometry: baseline $baseline on $dir" >&2
  bash -c "$baseline \"\$1\"" baseline "$dir" >"$out/baseline.txt" 2>&1 ||
    { cat "$out/baseline.txt" >&2; echo "bench_odometry: the baseline failed" >&2; exit 1; }
  if [ -n "$baseline_poses" ]; then
    [ "$baseline_pose_at" = auto ] && { [ -d "$dir/point_times" ] && baseline_pose_at=end || baseline_pose_at=start; }
    base_args=()
    [ -n "$calib" ] && base_args+=(--calib "$calib")
    [ -n "$lengths" ] && base_args+=(--lengths "$lengths")
    "$root/scripts/score_peer.sh" "$build" "$gt" "$baseline_poses" "$out/baseline_eval.json" \
      --pose-at "$baseline_pose_at" -- "${base_args[@]}" >"$out/baseline_eval.txt"
  fi
fi

# The rates of each pair, socc's first: this run's, then --repeat's further pairs, each socc run
# with a fresh map server on its own port (the first one's map stays for the report below).
rate_of() { sed -n 's/.*rate: \([0-9.]*\) Hz.*/\1/p' "$1" | head -1; }
fps_of() { sed -n 's/.*fps=\([0-9.]*\).*/\1/p' "$1" | head -1; }
echo "$(rate_of "$out/client_summary.txt") $(fps_of "$out/baseline.txt")" >"$out/rates.txt"
for ((run = 2; run <= repeat; run++)); do
  echo "bench_odometry: run $run of $repeat" >&2
  run_out="$out/run_$run"
  mkdir -p "$run_out"
  run_url="$(private_url)"
  start_server "$run_url" "$run_out/server.log" || true  # a run without rate is left out
  run_server=$started
  "$build/odom_client/odom_client" --kitti "$dir" --lcm-url "$run_url" --robot-id bench \
    --out-dir "$run_out" --no-revised "${client_args[@]}" >"$run_out/client_summary.txt" 2>/dev/null || true
  stop_server "$run_server"
  run_server=""
  : >"$run_out/baseline.txt"
  [ -n "$baseline" ] && { bash -c "$baseline \"\$1\"" baseline "$dir" >"$run_out/baseline.txt" 2>&1 || true; }
  echo "$(rate_of "$run_out/client_summary.txt") $(fps_of "$run_out/baseline.txt")" >>"$out/rates.txt"
done

stats="$("${cli[@]}" stats)"
echo "$stats" >"$out/server_stats.txt"
# Top-down map images of the whole run (bounding box of the trajectory + sensor range). The
# occupancy image is a slice from 1.2 m below to 2 m above the sensor path: obstacles and free
# space at robot height, not the occupied ground every column holds.
read -r box occ_box <<<"$(awk '{x=$4; y=$8; z=$12; if (NR==1||x<x0) x0=x; if (NR==1||x>x1) x1=x;
            if (NR==1||y<y0) y0=y; if (NR==1||y>y1) y1=y; if (NR==1||z<z0) z0=z; if (NR==1||z>z1) z1=z}
            END {printf "%.1f,%.1f,-5,%.1f,%.1f,30 %.1f,%.1f,%.1f,%.1f,%.1f,%.1f", x0-60, y0-60, x1+60,
                 y1+60, x0-60, y0-60, z0-1.2, x1+60, y1+60, z1+2}' "$out/poses_kitti.txt")"
# The estimate and the GT (moved to start where the estimate starts) drawn on both images.
tracks=(--trajectory "$out/poses_kitti.txt" --gt "$gt")
[ -n "$calib" ] && tracks+=(--gt-calib "$calib")
# shellcheck disable=SC2086
"${cli[@]}" render --box ${box//,/ } --mode 0 "${tracks[@]}" --title "$(basename "$dir"): classes" \
  --out "$out/map_class.png" >/dev/null
# shellcheck disable=SC2086
"${cli[@]}" render --box ${occ_box//,/ } --mode 1 "${tracks[@]}" \
  --title "$(basename "$dir"): occupancy at robot height" --out "$out/map_occupancy.png" >/dev/null

python3 - "$out" "$stats" "$baseline" "$judge" <<'PY'
import csv, json, os, re, sys
out, stats, baseline, judge = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "1"
ev = json.load(open(f"{out}/eval.json"))
rows = list(csv.DictReader(open(f"{out}/frames.csv")))
mean = lambda k: sum(float(r[k]) for r in rows) / max(len(rows), 1)
def pct(k, q):
    v = sorted(float(r[k]) for r in rows)
    return v[int(q * (len(v) - 1))] if v else 0.0
# One line per run: socc's Hz, then the baseline's fps when there is one (a failed run: none).
runs = [l.split() for l in open(f"{out}/rates.txt")]
def median(v):
    v = sorted(v)
    return (v[(len(v) - 1) // 2] + v[len(v) // 2]) / 2 if v else None
hz_runs = [float(r[0]) for r in runs if r]
base_runs = [float(r[1]) for r in runs if len(r) > 1]
pairs = [float(r[0]) / float(r[1]) for r in runs if len(r) > 1 and float(r[1]) > 0]
hz = median(hz_runs) or 0.0
base_fps = median(base_runs)
ratio = median(pairs)
def spread(v):
    return f", median of {len(v)} runs ({min(v):.1f}-{max(v):.1f})" if len(v) > 1 else ""
client_cpu, server_cpu = (float(x) for x in open(f"{out}/cpu.txt").read().split())
cpu_per_frame = (f"{1000 * client_cpu / max(len(rows), 1):.1f} / "
                 f"{1000 * server_cpu / max(len(rows), 1):.1f} ms (process start included)")
mem = re.search(r"memory_bytes=(\d+)", stats)
vox = re.search(r"voxels=(\d+)", stats)
base_ev = json.load(open(f"{out}/baseline_eval.json")) if os.path.exists(f"{out}/baseline_eval.json") else None
def fmt(v, unit=""):
    return "n/a" if v is None else f"{v:.3f}{unit}"
def acc(e):
    if e is None:
        return ["", "", ""]
    k = e["kitti"]
    return [fmt(k.get("t_err_percent"), " %"), fmt(k.get("r_err_deg_per_100m"), " deg/100m"),
            f"{e['ate_m']['rmse']:.3f} / {e['ate_m']['max']:.3f} m"]
sa, ba = acc(ev), acc(base_ev)
table = [
    ("frames", str(ev["frames"]), ""),
    ("path length (GT)", f"{ev['gt_length_m']:.1f} m", ""),
    ("KITTI t_err", sa[0], ba[0]),
    ("KITTI r_err", sa[1], ba[1]),
    ("ATE RMSE / max", sa[2], ba[2]),
    ("RPE trans / rot RMSE", f"{ev['rpe_trans_m']['rmse']:.3f} m / {ev['rpe_rot_deg']['rmse']:.3f} deg", ""),
    ("rate", f"{hz:.1f} Hz end to end (client + server, files read){spread(hz_runs)}",
     f"{base_fps:.1f} fps as it reports{spread(base_runs)}" if base_fps else ""),
    ("frame time mean / median / p99", f"{mean('total_ms'):.1f} / {pct('total_ms', 0.5):.1f} / {pct('total_ms', 0.99):.1f} ms", ""),
    ("preprocess", f"{mean('preprocess_ms'):.1f} ms/frame", ""),
    ("registration target (wait + overlay)", f"{mean('fetch_ms'):.1f} ms/frame (map build {mean('map_build_ms'):.1f})", ""),
    ("register", f"{mean('register_ms'):.1f} ms/frame", ""),
    ("wait for the previous frame", f"{mean('wait_ms'):.1f} ms/frame", ""),
    ("CPU a frame: client / server", cpu_per_frame, ""),
    ("GET_CHUNK / INTEGRATE round trip (worker)", f"{mean('chunk_ms'):.1f} / {mean('integrate_ms'):.1f} ms", ""),
    ("chunk traffic", f"{mean('bytes_received') / 1024:.0f} KiB/frame ({mean('chunk_voxels'):.0f} voxels)", ""),
    ("Integrate upload", f"{mean('bytes_sent') / 1024:.0f} KiB/frame", ""),
    ("server map", f"{int(vox.group(1)) if vox else 0} voxels, {int(mem.group(1)) / 2**20 if mem else 0:.1f} MiB"
     + (f", {int(mem.group(1)) / max(int(vox.group(1)), 1):.1f} B/voxel" if mem and vox else ""), ""),
]
print(f"| metric | socc | {'baseline' if baseline else ''} |\n|---|---|---|")
for name, value, base in table:
    print(f"| {name} | {value} | {base} |")
checks = []
if ratio is not None:
    of = f" (median of {len(pairs)} pairs)" if len(pairs) > 1 else ""
    checks.append((f"end to end >= 1.2x the baseline ({base_fps:.1f} fps): {hz:.1f} Hz = {ratio:.2f}x{of}", ratio >= 1.2))
else:
    checks.append((f"end to end >= 35 Hz (no baseline): {hz:.1f} Hz", hz >= 35.0))
med, p99 = pct("total_ms", 0.5), pct("total_ms", 0.99)
checks.append((f"frame time p99 <= 3x median: {p99:.1f} / {med:.1f} ms", p99 <= 3.0 * med))
checks.append((f"chunk traffic <= 300 KiB/frame: {mean('bytes_received') / 1024:.0f}", mean("bytes_received") <= 300 * 1024))
checks.append((f"Integrate upload <= 1 MB/frame: {mean('bytes_sent') / 1e6:.2f} MB", mean("bytes_sent") <= 1e6))
print()
for what, ok in checks:
    print(f"- target {what} -> {'PASS' if ok else 'FAIL'}")
print(f"\nPlots: {out}/plots/*.png; map images: {out}/map_class.png, {out}/map_occupancy.png")
sys.exit(0 if not judge or all(ok for _, ok in checks) else 1)
PY
