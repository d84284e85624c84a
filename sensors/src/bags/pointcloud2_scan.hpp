#pragma once
// sensor_msgs/PointCloud2 of any common layout -> SensorScan (docs/sensors_bags.md, "PointCloud2
// fields"). Fields are found by name: x, y, z (float32 or float64); intensity, else reflectivity
// (any numeric type); ring, else channel (any integer type); the first of t, time, offset_time,
// time_stamp, timestamp as the point time, its unit and reference told apart by datatype and
// value range (timeRule in the .cpp). Points with a non-finite coordinate and (0, 0, 0), the
// no-return placeholder of organized clouds, are dropped.
#include <cstdint>
#include <string>

#include "bags/ros_messages.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors::bags {

struct PointCloud2Conversion {
  SensorScan scan;
  std::uint64_t dropped_points = 0;  // non-finite or (0, 0, 0) coordinates, non-finite times
  std::string time_field;            // the field the times came from; empty: none
  std::string time_problem;          // why a time field present was not used; empty: none
};

/// Throws FormatError when the layout cannot be read: no float x/y/z, a field past
/// point_step, rows past the data, a non-integer ring.
PointCloud2Conversion convertPointCloud2(const PointCloud2Msg& cloud,
                                         std::int64_t receive_stamp_ns);

}  // namespace socc::sensors::bags
