#!/usr/bin/env python3
"""Median and max error of a TUM trajectory (stamp tx ty tz qx qy qz qw) against KITTI-layout GT
poses (3x4 per line, row k at stamp k * period).

Usage: tum_vs_gt.py TUM GT [--period 0.1]
Prints "poses N median_m M median_deg D max_m X max_deg Y"."""
import math
import sys


def rotation_of_quaternion(x, y, z, w):
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def angle_deg(a, b):
    # trace(a^T b) = 1 + 2 cos(angle)
    trace = sum(a[i][j] * b[i][j] for i in range(3) for j in range(3))
    return math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1.0) / 2.0))))


def median(values):
    s = sorted(values)
    mid = len(s) // 2
    return s[mid] if len(s) % 2 else 0.5 * (s[mid - 1] + s[mid])


def main():
    args = sys.argv[1:]
    period = 0.1
    if "--period" in args:
        i = args.index("--period")
        period = float(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    gt = [list(map(float, line.split())) for line in open(args[1]) if line.strip()]
    dt, dr = [], []
    for line in open(args[0]):
        v = list(map(float, line.split()))
        if len(v) != 8:
            continue
        row = gt[int(round(v[0] / period))]
        g_rot = [row[0:3], row[4:7], row[8:11]]
        g_t = [row[3], row[7], row[11]]
        dt.append(math.dist(v[1:4], g_t))
        dr.append(angle_deg(rotation_of_quaternion(*v[4:8]), g_rot))
    if not dt:
        sys.exit("no poses in " + args[0])
    print("poses %d median_m %.4f median_deg %.4f max_m %.4f max_deg %.4f" %
          (len(dt), median(dt), median(dr), max(dt), max(dr)))


if __name__ == "__main__":
    main()
