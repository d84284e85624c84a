#!/usr/bin/env bash
# Scores a peer odometry's poses against a sequence's ground truth with socc-eval (KITTI t_err,
# ATE, RPE as JSON; socc-eval's text report on stdout). Deskewing peers (KISS-ICP, GenZ-ICP)
# report each pose at the END of its sweep, the next sweep's start, where socc-sim's poses.txt
# gives the sweep's start: estimate k is compared with ground-truth pose k + 1 (--pose-at end,
# the default); --pose-at start compares them index by index. Arguments after -- go to socc-eval
# (e.g. --calib, --lengths). The one scoring of peers that the benchmark scripts share.
#
# Usage: scripts/score_peer.sh BUILD GT_POSES EST_POSES OUT_JSON [--pose-at end|start] [-- ARGS]
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
build="$1" gt="$2" est="$3" json="$4" pose_at="end"
shift 4
if [ "${1:-}" = --pose-at ]; then pose_at="${2:?--pose-at end|start}"; shift 2; fi
[ "${1:-}" = -- ] && shift
if [ "$pose_at" = end ]; then
  tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
  tail -n +2 "$gt" >"$tmp/gt.txt"; gt="$tmp/gt.txt"
  head -n -1 "$est" >"$tmp/est.txt"; est="$tmp/est.txt"
fi
"$build/eval/socc-eval" --gt "$gt" --est "$est" --truncate --json "$json" "$@"
