#!/usr/bin/env bash
# The main job on the embedded default: installs dependencies, builds, generates a synthetic
# urban LiDAR sequence with exact ground truth (socc-sim: streets, facades, poles, trees, parked
# and moving cars, pedestrians), runs map_server + odom_client on it over LCM (multicast on
# loopback), and prints the benchmark table. Results (poses, plots, map images) go to out/demo.
# Usage: scripts/demo.sh [--frames N] [--seed S]  (no downloads)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
frames=100; seed=1
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "demo: unknown argument $1" >&2; exit 2 ;;
  esac
done
cd "$root"
bash scripts/setup.sh
bash scripts/build.sh "$root/build"
out="$root/out/demo"
rm -rf "$out/seq"
mkdir -p "$out"
"$root/build/sim/socc-sim" --out "$out/seq" --frames "$frames" --seed "$seed"
# The synthetic run is ~90 m long: score KITTI-style errors over 10-80 m sub-sequences.
bash scripts/bench_odometry.sh "$out/seq" --build "$root/build" --out "$out" --lengths 10,20,30,40,50,60,70,80
