#!/usr/bin/env python3
"""Compares odom_client's per-laser range calibration with a simulated sensor's truth.

Usage: scripts/range_calibration_truth.py RANGE_CALIBRATION_TXT BEAMS_TXT
           [--vertical-correction DEG] [--ranges 10,20,40]

RANGE_CALIBRATION_TXT: odom_client's range_calibration.txt (elevation_deg offset_m scale per
laser; a range r is corrected to r - offset - scale * r). BEAMS_TXT: socc-sim's beams.txt (the
sensor instance's truth: reported range = true range * (1 + range_scale) + range_offset).
A laser of the calibration is matched to the simulated laser whose nominal elevation plus the
client's vertical_angle_correction_deg (odom_client/config/kitti.yaml: 0.205) falls in its
0.1-deg bin. Prints, per laser and as RMS over the lower and the upper half of the lasers, the
range error left at each range without the correction and with it (truth minus estimate).
"""
import argparse
import math
import sys


def rows(path):
    out = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                out.append([float(x) for x in line.split()])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("calibration")
    ap.add_argument("beams")
    ap.add_argument("--vertical-correction", type=float, default=0.205)
    ap.add_argument("--ranges", default="10,20,40")
    a = ap.parse_args()
    ranges = [float(r) for r in a.ranges.split(",")]
    beams = rows(a.beams)  # nominal_elev, elev_err, az_err, offset, scale
    estimates = rows(a.calibration)  # elevation_deg, offset, scale
    pairs = []
    for elevation, offset, scale in estimates:
        near = [b for b in beams
                if abs(b[0] + a.vertical_correction - elevation) <= 0.05 + 1e-6]
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


if __name__ == "__main__":
    main()
