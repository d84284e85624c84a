#!/usr/bin/python3
"""Writes ROS 1 bags of real scans with Debian's python3-rosbag (the ROS project's own writer,
independent of socc's reader; test_bags reads them back bit for bit):
    /usr/bin/python3 write_ros1_bags.py OUT_DIR SCAN.bin...
For each chunk compression (none, bz2, lz4) OUT_DIR/clouds_<compression>.bag holds
    /points      sensor_msgs/PointCloud2: x y z intensity float32 (the KITTI layout, as is)
    /points_f64  sensor_msgs/PointCloud2: x y z float64, intensity float32, timestamp float64
                 = absolute seconds (header stamp + point index * 1e-6 s)
    /chatter     std_msgs/String (a topic socc does not read)
Scan i has header stamp 1700000000 + i s + 500 ns and record time 1 ms later.
"""
import os
import struct
import sys

import genpy
import rosbag
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import String


def cloud(stamp, fields, point_step, width, data):
    m = PointCloud2()
    m.header.stamp = stamp
    m.header.frame_id = "velodyne"
    m.height = 1
    m.width = width
    m.fields = fields
    m.is_bigendian = False
    m.point_step = point_step
    m.row_step = point_step * width
    m.data = data
    m.is_dense = True
    return m


def kitti_cloud(stamp, raw):
    fields = [PointField(name, 4 * k, PointField.FLOAT32, 1)
              for k, name in enumerate(("x", "y", "z", "intensity"))]
    return cloud(stamp, fields, 16, len(raw) // 16, raw)


def float64_cloud(stamp, raw):
    n = len(raw) // 16
    values = struct.unpack("<%df" % (4 * n), raw)
    out = bytearray(36 * n)
    t0 = stamp.to_sec()
    for i in range(n):
        x, y, z, intensity = values[4 * i:4 * i + 4]
        struct.pack_into("<dddfd", out, 36 * i, x, y, z, intensity, t0 + i * 1e-6)
    fields = [PointField("x", 0, PointField.FLOAT64, 1), PointField("y", 8, PointField.FLOAT64, 1),
              PointField("z", 16, PointField.FLOAT64, 1),
              PointField("intensity", 24, PointField.FLOAT32, 1),
              PointField("timestamp", 28, PointField.FLOAT64, 1)]
    return cloud(stamp, fields, 36, n, bytes(out))


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: write_ros1_bags.py OUT_DIR SCAN.bin...")
    out_dir = sys.argv[1]
    scans = [open(f, "rb").read() for f in sys.argv[2:]]
    os.makedirs(out_dir, exist_ok=True)
    for compression in ("none", "bz2", "lz4"):
        path = os.path.join(out_dir, "clouds_%s.bag" % compression)
        with rosbag.Bag(path, "w", compression=compression) as bag:
            for i, raw in enumerate(scans):
                stamp = genpy.Time(1700000000 + i, 500)
                record = genpy.Time(1700000000 + i, 1000500)
                bag.write("/points", kitti_cloud(stamp, raw), record)
                bag.write("/points_f64", float64_cloud(stamp, raw), record)
                bag.write("/chatter", String(data="scan %d" % i), record)


if __name__ == "__main__":
    main()
