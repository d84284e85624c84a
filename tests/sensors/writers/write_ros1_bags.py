#!/usr/bin/python3
"""Writes ROS 1 bags of real scans with Debian's python3-rosbag (the ROS project's own writer,
independent of socc's reader; test_bags reads them back bit for bit):
    /usr/bin/python3 write_ros1_bags.py OUT_DIR SCAN.bin...
For each chunk compression (none, bz2, lz4) OUT_DIR/clouds_<compression>.bag holds
    /points      sensor_msgs/PointCloud2: x y z intensity float32 (the KITTI layout, as is)
    /points_f64  sensor_msgs/PointCloud2: x y z float64, intensity float32, timestamp float64
                 = absolute seconds (header stamp + point index * 1e-6 s)
    /chatter     std_msgs/String (a topic socc does not read)
    /imu         sensor_msgs/Imu: 21 samples at 10 Hz from 1699999999.5 s (imu_sample below)
    /tf_static   tf2_msgs/TFMessage: /base_link -> velodyne at (0, 0, 1.7), base_link -> imu at
                 (0.1, 0, 0.5) turned 90 deg about z (so velodyne_R_imu is that turn)
Scan i has header stamp 1700000000 + i s + 500 ns and record time 1 ms later.
"""
import math
import os
import struct
import sys

import genpy
import rosbag
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import Imu, PointCloud2, PointField
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage


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


def imu_sample(k):
    """Sample k of /imu (write_mcap_clouds.cjs writes the same): header stamp 1699999999.5 s +
    0.1 k s; orientation a turn of 0.01 k rad about x; orientation covariance diag(1e-4, 4e-4,
    1e-2), but [0] = -1 (no orientation) for k = 5; angular velocity (0.1, 0.2, 0.3 + k) rad/s;
    linear acceleration (0.5, -0.25, 9.81) m/s^2."""
    m = Imu()
    m.header.stamp = genpy.Time(1699999999 + (5 + k) // 10, ((5 + k) % 10) * 100000000)
    m.header.frame_id = "imu"
    m.orientation.x = math.sin(0.005 * k)
    m.orientation.w = math.cos(0.005 * k)
    m.orientation_covariance = [1e-4, 0, 0, 0, 4e-4, 0, 0, 0, 1e-2]
    if k == 5:
        m.orientation_covariance[0] = -1.0
    m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = 0.1, 0.2, 0.3 + k
    m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = 0.5, -0.25, 9.81
    return m


def static_transforms():
    """The /tf_static message (write_mcap_clouds.cjs writes the same, without the leading '/')."""
    lidar = TransformStamped()
    lidar.header.stamp = genpy.Time(1699999999, 0)
    lidar.header.frame_id = "/base_link"
    lidar.child_frame_id = "velodyne"
    lidar.transform.translation.z = 1.7
    lidar.transform.rotation.w = 1.0
    imu = TransformStamped()
    imu.header.stamp = genpy.Time(1699999999, 0)
    imu.header.frame_id = "base_link"
    imu.child_frame_id = "imu"
    imu.transform.translation.x, imu.transform.translation.z = 0.1, 0.5
    imu.transform.rotation.z = math.sin(math.pi / 4)
    imu.transform.rotation.w = math.cos(math.pi / 4)
    return TFMessage(transforms=[lidar, imu])


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
            bag.write("/tf_static", static_transforms(), genpy.Time(1699999999, 0))
            for k in range(21):
                m = imu_sample(k)
                bag.write("/imu", m, m.header.stamp + genpy.Duration(0, 1000000))


if __name__ == "__main__":
    main()
