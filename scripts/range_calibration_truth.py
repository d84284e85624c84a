#!/usr/bin/env python3
"""Compares odom_client's per-laser range calibration with a simulated sensor's truth.

Usage: scripts/range_calibration_truth.py RANGE_CALIBRATION_TXT BEAMS_TXT
           [--vertical-correction DEG] [--ranges 10,20,40] [--sequence SEQ_DIR [--every N]]

RANGE_CALIBRATION_TXT: odom_client's range_calibration.txt (elevation_deg offset_m scale per
laser; a range r is corrected to r - offset - scale * r). BEAMS_TXT: socc-sim's beams.txt (the
sensor instance's truth: reported range = true range * (1 + range_scale) + range_offset).
A laser of the calibration is matched to the simulated laser whose nominal elevation plus the
client's vertical_angle_correction_deg (odom_client/config/kitti.yaml: 0.205) falls in its
0.1-deg bin. Prints, per laser and as RMS over the lower and the upper half of the lasers, the
range error left at each range without the correction and with it (truth minus estimate).
A laser measures only some ranges (one below about -10 deg meets a level road within 10 m), so
with --sequence (socc-sim's output the calibration was made on) it also prints the RMS range
error of the points themselves, before and after, over the ranges each laser measured there:
every N-th scan's points (velodyne/*.bin, default every 20th), each matched to its laser by its
elevation, lasers the calibration does not list counted as uncorrected.
"""
import argparse
import array
import bisect
import glob
import math
import os
import sys


def rows(path):
    out = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                out.append([float(x) for x in line.split()])
    return out


def in_bin(nominal, elevation, correction):
    """Whether a simulated laser of this nominal elevation is the calibration's laser (bin)."""
    return abs(nominal + correction - elevation) <= 0.05 + 1e-6


def match(calibration, nominal, correction):
    """The calibration's (offset, scale) for a laser of this nominal elevation, or None."""
    near = [(o, s) for e, o, s in calibration if in_bin(nominal, e, correction)]
    return near[0] if len(near) == 1 else None


def measured(sequence, every, beams, calibration, correction):
    """Per laser (by nominal elevation): point count, sums of squared range error before and
    after the correction, over every N-th scan's points."""
    elevations = sorted(b[0] for b in beams)
    truth = {b[0]: (b[3], b[4]) for b in beams}
    fix = {e: match(calibration, e, correction) or (0.0, 0.0) for e in elevations}
    sums = {e: [0, 0.0, 0.0] for e in elevations}
    scans = sorted(glob.glob(os.path.join(sequence, "velodyne", "*.bin")))[::every]
    if not scans:
        sys.exit("no scans in %s/velodyne" % sequence)
    for path in scans:
        values = array.array("f")
        with open(path, "rb") as f:
            values.frombytes(f.read())
        for i in range(0, len(values) - 3, 4):
            x, y, z = values[i], values[i + 1], values[i + 2]
            r = math.sqrt(x * x + y * y + z * z)
            if r <= 0.0:
                continue
            elevation = math.degrees(math.atan2(z, math.hypot(x, y)))
            k = bisect.bisect_left(elevations, elevation)
            e = min(elevations[max(k - 1, 0):k + 1], key=lambda v: abs(v - elevation))
            # The reported range holds the error: the true one is (r - offset) / (1 + scale).
            offset, scale = truth[e]
            error = r - (r - offset) / (1.0 + scale)
            c = sums[e]
            c[0] += 1
            c[1] += error * error
            c[2] += (error - fix[e][0] - fix[e][1] * r) ** 2
    return len(scans), sums


def print_measured(scans, sums, every):
    lasers = sorted(e for e in sums if sums[e][0] > 0)
    half = len(lasers) // 2
    for name, part in (("lower half", lasers[:half]), ("upper half", lasers[half:]),
                       ("all", lasers)):
        n = sum(sums[e][0] for e in part)
        if n == 0:
            continue
        before = math.sqrt(sum(sums[e][1] for e in part) / n)
        after = math.sqrt(sum(sums[e][2] for e in part) / n)
        print("%s (%d lasers, %d points of %d scans, every %d), RMS range error of the points "
              "at the ranges measured: %.4f -> %.4f m" % (name, len(part), n, scans, every,
                                                          before, after))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("calibration")
    ap.add_argument("beams")
    ap.add_argument("--vertical-correction", type=float, default=0.205)
    ap.add_argument("--ranges", default="10,20,40")
    ap.add_argument("--sequence", help="socc-sim sequence: error at the ranges each laser measured")
    ap.add_argument("--every", type=int, default=20, help="with --sequence: every N-th scan")
    a = ap.parse_args()
    ranges = [float(r) for r in a.ranges.split(",")]
    beams = rows(a.beams)  # nominal_elev, elev_err, az_err, offset, scale
    estimates = rows(a.calibration)  # elevation_deg, offset, scale
    pairs = []
    for elevation, offset, scale in estimates:
        near = [b for b in beams if in_bin(b[0], elevation, a.vertical_correction)]
        if len(near) != 1:
            print("laser at %.2f deg: %d simulated lasers in its bin, skipped" % (elevation, len(near)))
            continue
        pairs.append((near[0], offset, scale))
    if not pairs:
        sys.exit("no laser matched: check --vertical-correction")
    pairs.sort(key=lambda p: p[0][0])
    print("%-8s %-17s %-17s %s" % ("elev", "true off/scale", "est off/scale",
                                    "  ".join("err@%gm before->after" % r for r in ranges)))
    for beam, offset, scale in pairs:
        cells = []
        for r in ranges:
            true = beam[3] + beam[4] * r
            cells.append("%+.3f->%+.3f" % (true, true - offset - scale * r))
        print("%-8.3f %+.4f %+.5f  %+.4f %+.5f  %s" % (beam[0], beam[3], beam[4], offset, scale,
                                                      "  ".join(cells)))
    half = len(pairs) // 2
    for name, part in (("lower half", pairs[:half]), ("upper half", pairs[half:]), ("all", pairs)):
        cells = []
        for r in ranges:
            before = math.sqrt(sum((b[3] + b[4] * r) ** 2 for b, _, _ in part) / len(part))
            after = math.sqrt(sum((b[3] + b[4] * r - o - s * r) ** 2 for b, o, s in part) / len(part))
            cells.append("%.3f -> %.3f m" % (before, after))
        print("%s (%d lasers), RMS range error at %s m: %s" % (
            name, len(part), "/".join("%g" % r for r in ranges), ", ".join(cells)))
    if a.sequence:
        print_measured(*measured(a.sequence, max(a.every, 1), beams, estimates,
                                 a.vertical_correction), max(a.every, 1))


if __name__ == "__main__":
    main()
