#!/usr/bin/env bash
# Writes the bags test_bags reads back, with independent writers, from two real KITTI scans:
#   write_bag_fixtures.sh OUT_DIR SHARED_DATA_DIR
# ROS 1 bags with Debian's python3-rosbag (write_ros1_bags.py), MCAP files with @mcap/core
# under node (write_mcap_clouds.cjs; its npm packages are installed into OUT_DIR/node, never
# into the source tree). Exits 77 (skip) only when the shared data folder is absent.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="$1"
data="$2"
scans=("$data/kitti_00_first16/velodyne/000000.bin" "$data/kitti_00_first16/velodyne/000001.bin")
if [ ! -d "$data" ]; then
  echo "write_bag_fixtures: $data absent: skipping"
  exit 77
fi
mkdir -p "$out/node"
# Debian's python3 (python3-rosbag lives in its dist-packages), not a python3 earlier in PATH.
/usr/bin/python3 "$here/write_ros1_bags.py" "$out" "${scans[@]}"
cp "$here/package.json" "$here/write_mcap_clouds.cjs" "$out/node/"
if ! cmp -s "$here/package.json" "$out/node/.installed-package.json"; then
  npm install --prefix "$out/node" --no-audit --no-fund --no-package-lock --loglevel=error
  cp "$here/package.json" "$out/node/.installed-package.json"
fi
node "$out/node/write_mcap_clouds.cjs" "$out" "${scans[@]}"
ls -l "$out"/clouds_*
