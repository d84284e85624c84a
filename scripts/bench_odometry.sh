#!/usr/bin/env bash
# Odometry benchmark report: starts a map_server, runs odom_client on a KITTI-layout directory,
# evaluates against DIR/poses.txt (LiDAR frame; or --gt/--calib for KITTI camera-frame GT),
# prints ONE markdown table (accuracy, per-stage timing, Hz, bytes/frame, server memory), and
# writes trajectory/error plots (PNG) and top-down map images (by class, by occupancy) with
# a legend, a scale bar and both trajectories.
#
# Usage: scripts/bench_odometry.sh DIR [--build BUILD] [--out OUT] [--gt POSES] [--calib CALIB]
#                                  [--lengths 100,200,...] [--no-semantics] [--frames N]
#                                  [--config ODOM_YAML]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

[ $# -ge 1 ] || usage 2
case "$1" in -h|--help) usage 0 ;; esac
dir="$(cd "$1" && pwd)"; shift
build="$root/build"; out=""; gt=""; calib=""; lengths=""; client_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --gt) gt="$2"; shift 2 ;;
    --calib) calib="$2"; shift 2 ;;
    --lengths) lengths="$2"; shift 2 ;;
    --no-semantics) client_args+=(--no-semantics); shift ;;
    --config) client_args+=(--config "$2"); shift 2 ;;
    --frames) client_args+=(--last-frame "$(($2 - 1))"); shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "bench_odometry: unknown argument $1" >&2; usage 2 ;;
  esac
done
out="${out:-$root/out/bench_$(basename "$dir")}"
mkdir -p "$out"
gt="${gt:-$dir/poses.txt}"
for bin in map_server/map_server odom_client/odom_client eval/socc-eval tools/socc-cli; do
  [ -x "$build/$bin" ] || { echo "bench_odometry: $build/$bin missing: run scripts/build.sh" >&2; exit 2; }
done

# Private multicast port so concurrent runs never see each other; ttl=0 keeps it on this machine.
url="${SOCC_LCM_URL:-udpm://239.255.76.67:$((20000 + RANDOM % 40000))?ttl=0&recv_buf_size=33554432}"
cli=("$build/tools/socc-cli" --lcm-url "$url" --client-id bench)

"$build/map_server/map_server" --lcm-url "$url" --quiet >"$out/server.log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true' EXIT
for _ in $(seq 50); do "${cli[@]}" stats >/dev/null 2>&1 && break; sleep 0.2; done
"${cli[@]}" stats >/dev/null || { echo "bench_odometry: map_server did not answer" >&2; cat "$out/server.log" >&2; exit 1; }

echo "bench_odometry: odom_client on $dir" >&2
client_rc=0
"$build/odom_client/odom_client" --kitti "$dir" --lcm-url "$url" --robot-id bench \
  --out-dir "$out" "${client_args[@]}" | tee "$out/client_summary.txt" >&2 || client_rc=$?
# Exit 3: the robot declared itself lost (its frames.csv says where); still scored below.
[ "$client_rc" -eq 0 ] || [ "$client_rc" -eq 3 ] || { echo "bench_odometry: odom_client failed ($client_rc)" >&2; exit 1; }

eval_args=(--gt "$gt" --est "$out/poses_kitti.txt" --truncate --json "$out/eval.json" --plot-dir "$out/plots")
# KITTI layouts carry calib.txt: GT in the camera frame is converted with its Tr (identity for socc-sim).
[ -z "$calib" ] && [ -f "$dir/calib.txt" ] && calib="$dir/calib.txt"
[ -n "$calib" ] && eval_args+=(--calib "$calib")
[ -n "$lengths" ] && eval_args+=(--lengths "$lengths")
"$build/eval/socc-eval" "${eval_args[@]}" >"$out/eval.txt"

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

python3 - "$out" "$stats" <<'PY'
import csv, json, re, sys
out, stats = sys.argv[1], sys.argv[2]
ev = json.load(open(f"{out}/eval.json"))
rows = list(csv.DictReader(open(f"{out}/frames.csv")))
mean = lambda k: sum(float(r[k]) for r in rows) / max(len(rows), 1)
summary = open(f"{out}/client_summary.txt").read()
hz = re.search(r"rate: ([0-9.]+) Hz", summary)
mem = re.search(r"memory_bytes=(\d+)", stats)
vox = re.search(r"voxels=(\d+)", stats)
k = ev["kitti"]
def fmt(v, unit=""):
    return "n/a" if v is None else f"{v:.3f}{unit}"
table = [
    ("frames", str(ev["frames"])),
    ("path length (GT)", f"{ev['gt_length_m']:.1f} m"),
    ("KITTI t_err", fmt(k.get("t_err_percent"), " %")),
    ("KITTI r_err", fmt(k.get("r_err_deg_per_100m"), " deg/100m")),
    ("ATE RMSE / max", f"{ev['ate_m']['rmse']:.3f} / {ev['ate_m']['max']:.3f} m"),
    ("RPE trans RMSE", f"{ev['rpe_trans_m']['rmse']:.3f} m"),
    ("RPE rot RMSE", f"{ev['rpe_rot_deg']['rmse']:.3f} deg"),
    ("preprocess", f"{mean('preprocess_ms'):.1f} ms/frame"),
    ("fetch chunk", f"{mean('fetch_ms'):.1f} ms/frame (map build {mean('map_build_ms'):.1f})"),
    ("register", f"{mean('register_ms'):.1f} ms/frame"),
    ("integrate (wait)", f"{mean('integrate_ms'):.1f} ms/frame"),
    ("total", f"{mean('total_ms'):.1f} ms/frame"),
    ("end-to-end rate", f"{hz.group(1)} Hz" if hz else "n/a"),
    ("chunk traffic", f"{mean('bytes_received') / 1024:.0f} KiB/frame ({mean('chunk_voxels'):.0f} voxels)"),
    ("server map", f"{int(vox.group(1)) if vox else 0} voxels, {int(mem.group(1)) / 2**20 if mem else 0:.1f} MiB"),
]
print("| metric | value |\n|---|---|")
for name, value in table:
    print(f"| {name} | {value} |")
print(f"\nPlots: {out}/plots/*.png; map images: {out}/map_class.png, {out}/map_occupancy.png")
PY
