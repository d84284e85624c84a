#!/usr/bin/env python3
"""What the consistency service measured, against a simulated sequence's truth: how far its
closures' and odometry edges' relative poses are from the ground truth's, the mean tilt of the
optimized keyframes' attitudes (the map's tilt), and how far the first frame's gravity reading is
from the truth's up direction (docs/consistency.md "What is left on the full drive").

The truth's up in the map frame (the first pose's frame) is the mean of all gravity readings
turned into it by the ground truth: the readings' noise and slow bias average out over a drive.

Usage: scripts/consistency_truth.py CONSISTENCY_DIR SEQ_DIR
  CONSISTENCY_DIR: what map_server --consistency-dir wrote at its stop (keyframes.txt,
  closures.txt), e.g. OUT/consistency of scripts/bench_consistency.sh; SEQ_DIR: the sequence
  (poses.txt, LiDAR frame; gravity.txt when the simulator had an --imu).
"""
import math
import os
import sys


def pose(values):
    """A 3x4 row-major pose as (rotation rows, translation)."""
    v = [float(x) for x in values]
    return [v[0:3], v[4:7], v[8:11]], [v[3], v[7], v[11]]


def rotate(r, u):
    return [sum(r[i][k] * u[k] for k in range(3)) for i in range(3)]


def transpose(r):
    return [[r[k][i] for k in range(3)] for i in range(3)]


def relative(a, b):
    """a^-1 * b."""
    ra, ta = a
    rb, tb = b
    rt = transpose(ra)
    r = [[sum(rt[i][k] * rb[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return r, rotate(rt, [tb[i] - ta[i] for i in range(3)])


def small_angles(r):
    """A small rotation's angles about x, y, z [deg]."""
    return [math.degrees((r[2][1] - r[1][2]) / 2), math.degrees((r[0][2] - r[2][0]) / 2),
            math.degrees((r[1][0] - r[0][1]) / 2)]


def error(measured, truth):
    """Translation [m] and small angles [deg] of truth^-1 * measured."""
    r, t = relative(truth, measured)
    return math.sqrt(sum(x * x for x in t)), small_angles(r)


def angle(a, b):
    """Between two directions [deg]."""
    cosine = sum(x * y for x, y in zip(a, b)) / math.sqrt(
        sum(x * x for x in a) * sum(y * y for y in b))
    return math.degrees(math.acos(min(1.0, cosine)))


def median(values):
    return sorted(values)[len(values) // 2]


def spread(values):
    mean = sum(values) / len(values)
    return math.sqrt(sum((x - mean) ** 2 for x in values) / len(values))


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    cons, seq = sys.argv[1], sys.argv[2]
    with open(os.path.join(seq, "poses.txt")) as f:
        truth = [pose(line.split()) for line in f]
    keyframes = []  # seq, odometry pose, optimized pose
    with open(os.path.join(cons, "keyframes.txt")) as f:
        for line in f:
            v = line.split()
            keyframes.append((int(v[1]), pose(v[2:14]), pose(v[14:26])))
    closures = []  # (from seq, to seq, measured relative pose)
    with open(os.path.join(cons, "closures.txt")) as f:
        for line in f:
            v = line.split()
            closures.append((int(v[1]), int(v[3]), pose(v[4:16])))

    if closures:
        # Either direction may be stored: the one nearer the truth is the closure's.
        errs = [min(error(m, relative(truth[a], truth[b])), error(m, relative(truth[b], truth[a])))
                for a, b, m in closures]
        print("closures: %d; against the truth %.3f m / %.3f deg heading (median), "
              "%.3f m / %.3f deg at most" %
              (len(errs), median([e[0] for e in errs]), median([abs(e[1][2]) for e in errs]),
               max(e[0] for e in errs), max(abs(e[1][2]) for e in errs)))
    edges = [error(relative(a[1], b[1]), relative(truth[a[0]], truth[b[0]]))
             for a, b in zip(keyframes, keyframes[1:])]
    if edges:
        print("odometry edges: %d; against the truth (standard deviation) %.3f m, roll %.3f / "
              "pitch %.3f / heading %.3f deg" %
              (len(edges), spread([e[0] for e in edges]), spread([e[1][0] for e in edges]),
               spread([e[1][1] for e in edges]), spread([e[1][2] for e in edges])))
    tilts = [small_angles(relative(truth[s], optimized)[0]) for s, _, optimized in keyframes]
    if tilts:
        # The attitude error turned into the map frame: a tilt of the whole map is its mean.
        world = [rotate(truth[s][0], t) for (s, _, _), t in zip(keyframes, tilts)]
        print("optimized keyframes' attitude error in the map frame, mean: x %+.3f y %+.3f deg" %
              (sum(w[0] for w in world) / len(world), sum(w[1] for w in world) / len(world)))
    gravity_file = os.path.join(seq, "gravity.txt")
    if os.path.exists(gravity_file):
        with open(gravity_file) as f:
            readings = [[float(x) for x in line.split()[:3]] for line in f]
        total = [0.0, 0.0, 0.0]
        for (r, _), u in zip(truth, readings):
            total = [a + b for a, b in zip(total, rotate(r, u))]
        norm = math.sqrt(sum(x * x for x in total))
        up = [x / norm for x in total]
        print("first gravity reading against the truth's up: %.4f deg (truth's up in the map "
              "frame: %.9f %.9f %.9f)" % (angle(readings[0], up), *up))
        # What averaging the readings of the first second would leave (turned exactly).
        times = [0.1 * i for i in range(len(readings))]
        times_file = os.path.join(seq, "times.txt")
        if os.path.exists(times_file):
            with open(times_file) as f:
                times = [float(line) for line in f]
        first = [0.0, 0.0, 0.0]
        for (r, _), u, t in zip(truth, readings, times):
            if t - times[0] < 1.0:
                first = [a + b for a, b in zip(first, rotate(r, u))]
        print("mean of the first second's readings against it: %.4f deg" % angle(first, up))
    return 0


if __name__ == "__main__":
    sys.exit(main())
