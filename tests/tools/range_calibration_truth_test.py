#!/usr/bin/env python3
"""scripts/range_calibration_truth.py on a made-up sensor: lasers corrected exactly leave no
range error, a laser left uncorrected keeps its own, a laser without a simulated one is named;
with --sequence the same over the points of a scan, each at the range it was measured.
Usage: range_calibration_truth_test.py SCRIPT"""
import math
import os
import struct
import subprocess
import sys
import tempfile


def main():
    script = sys.argv[1]
    with tempfile.TemporaryDirectory() as d:
        beams = os.path.join(d, "beams.txt")
        calibration = os.path.join(d, "range_calibration.txt")
        with open(beams, "w") as f:
            f.write("# nominal_elevation_deg elevation_error_deg azimuth_error_deg range_offset_m range_scale\n")
            f.write("-10.0000 0.1 0.0 0.02000 0.001000\n")
            f.write("-5.0000 0.1 0.0 -0.01000 -0.002000\n")
            f.write("0.0000 0.1 0.0 0.01000 0.000000\n")
            f.write("5.0000 0.1 0.0 0.00000 0.003000\n")
        with open(calibration, "w") as f:  # elevation bins of 0.1 deg, 0.205 deg correction
            f.write("# elevation_deg offset_m scale\n")
            f.write("-9.75 0.0200 0.001000\n")   # -10 + 0.205: exact
            f.write("-4.75 0.0000 0.000000\n")   # -5: not corrected
            f.write("0.25 0.0100 0.000000\n")    # 0: exact
            f.write("5.25 0.0000 0.003000\n")    # 5: exact
            f.write("9.95 0.0000 0.000000\n")    # no simulated laser there
        # One scan: the -10 deg laser (corrected exactly) reports 10.03 m for a true 10 m, the
        # -5 deg laser (not corrected) 19.95 m for a true 20 m.
        os.makedirs(os.path.join(d, "velodyne"))
        with open(os.path.join(d, "velodyne", "000000.bin"), "wb") as f:
            for elevation, reported in ((-10.0, 10.03), (-5.0, 19.95)):
                e = math.radians(elevation)
                f.write(struct.pack("4f", reported * math.cos(e), 0.0, reported * math.sin(e), 0.5))
        out = subprocess.run([sys.executable, script, calibration, beams, "--ranges", "10",
                              "--sequence", d], check=True, capture_output=True, text=True).stdout
    print(out)
    assert "laser at 9.95 deg: 0 simulated lasers in its bin, skipped" in out, out
    # The uncorrected laser keeps -0.01 - 0.002 x 10 = -0.030 m; the exact ones leave none.
    assert "-0.030->-0.030" in out, out
    assert "+0.030->+0.000" in out and "+0.010->+0.000" in out, out
    lower = [l for l in out.splitlines() if l.startswith("lower half")][0]
    # Before: 0.030 and 0.030 m; after: 0 and 0.030 m, RMS 0.021 m.
    assert "(2 lasers)" in lower and "0.030 -> 0.021 m" in lower, lower
    upper = [l for l in out.splitlines() if l.startswith("upper half")][0]
    assert "0.000 m" in upper.split("->")[-1], upper
    # Over the points: the -10 deg laser 0.030 -> 0 m, the -5 deg one -0.050 m before and after.
    points = [l for l in out.splitlines() if "at the ranges measured" in l]
    assert len(points) == 3, out
    assert "(1 lasers, 1 points of 1 scans" in points[0] and "0.0300 -> 0.0000 m" in points[0], out
    assert "0.0500 -> 0.0500 m" in points[1], out
    assert "(2 lasers, 2 points" in points[2] and "0.0412 -> 0.0354 m" in points[2], out


if __name__ == "__main__":
    main()
