#!/usr/bin/env bash
# The main job on the embedded default (no downloads): installs dependencies, builds, generates a
# synthetic urban drive with exact ground truth (socc-sim: a figure-eight with turns and a loop
# through streets with facades, poles, trees, parked and moving cars and walking people, with
# motion distortion: per-point times), then over LCM (multicast on loopback):
#   1. the paper's ablation on that drive: SOCC-ICP with semantics, without semantics, and a
#      plain point-to-point baseline (odom_client/config/baseline.yaml), each against a fresh
#      map_server, in one table;
#   2. two robots mapping the drive together (each half of it, at the same time, one map_server),
#      compared with each alone, and the map image with both trajectories over the GT.
# Results (poses, plots, map images) go to out/demo.
# The drive is simulated with --realism kitti (sensor, ground, vehicle and label errors as on real
# KITTI data; sim/README.md "Realism"); --realism none gives the exact simulator.
# Usage: scripts/demo.sh [--frames N] [--seed S] [--realism kitti|none]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
frames=200; seed=1; realism=kitti
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --realism) realism="$2"; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "demo: unknown argument $1" >&2; exit 2 ;;
  esac
done
cd "$root"
bash scripts/setup.sh
bash scripts/build.sh "$root/build"
out="$root/out/demo"
rm -rf "$out"
mkdir -p "$out"
sim=(--scene street --trajectory figure8 --distortion --seed "$seed" --realism "$realism")
"$root/build/sim/socc-sim" --out "$out/seq" --frames "$frames" "${sim[@]}"

variants=("socc:SOCC-ICP (semantics):"
          "no_semantics:SOCC-ICP without semantics:--no-semantics"
          "baseline:point-to-point baseline:--config $root/odom_client/config/baseline.yaml")
for v in "${variants[@]}"; do
  IFS=: read -r dir name args <<<"$v"
  echo "demo: $name" >&2
  # shellcheck disable=SC2086  # args: option words
  bash scripts/bench_odometry.sh "$out/seq" --build "$root/build" --out "$out/$dir" \
    --lengths 20,40,60,80,100 --no-targets $args >"$out/$dir.md"
done

echo "demo: two robots, one map" >&2
# Its PASS/FAIL compares aligned ATE with each robot alone; the demo reports it, it does not gate.
bash scripts/demo_multirobot.sh --robots 2 --frames $((frames / 2)) --seed "$seed" \
  --trajectory figure8 --distortion --realism "$realism" --build "$root/build" --out "$out/two_robots" \
  >"$out/two_robots.md" || true

SOCC_REALISM="$realism" python3 - "$out" "${variants[@]}" <<'PY'
import json, os, re, sys
out, variants = sys.argv[1], sys.argv[2:]
print(f"## socc demo: a {json.load(open(f'{out}/socc/eval.json'))['gt_length_m']:.0f} m "
      "figure-eight drive with motion distortion, moving cars and people "
      f"(socc-sim --realism {os.environ['SOCC_REALISM']}, exact GT)\n")
print("| method | KITTI t_err | r_err [deg/100 m] | ATE RMSE / max [m] | RPE trans / rot per frame | Hz |")
print("|---|---|---|---|---|---|")
for v in variants:
    d, name = v.split(":")[:2]
    ev = json.load(open(f"{out}/{d}/eval.json"))
    k = ev["kitti"]
    hz = re.search(r"rate: ([0-9.]+) Hz", open(f"{out}/{d}/client_summary.txt").read())
    fmt = lambda x, f: "n/a" if x is None else f % x
    print(f"| {name} | {fmt(k.get('t_err_percent'), '%.3f %%')} | "
          f"{fmt(k.get('r_err_deg_per_100m'), '%.4f')} | "
          f"{ev['ate_m']['rmse']:.3f} / {ev['ate_m']['max']:.3f} | "
          f"{ev['rpe_trans_m']['rmse']:.4f} m / {ev['rpe_rot_deg']['rmse']:.4f} deg | "
          f"{hz.group(1) if hz else 'n/a'} |")
print("\n### Two robots, one map (each half of the drive at the same time, vs alone)\n")
print(open(f"{out}/two_robots.md").read())
print(f"Map images: {out}/socc/map_class.png, {out}/socc/map_occupancy.png (one robot, estimate "
      f"and GT), {out}/two_robots/map_class.png (both robots over the GT). Per-method tables, "
      f"plots and frames.csv: {out}/<method>/.")
PY
