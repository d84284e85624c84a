#include "socc/tools/sensor_scan_message.hpp"

#include <algorithm>

#include "socc/wire_arrays.hpp"

namespace socc::tools {

scan_t toScanMessage(const sensors::SensorScan& sweep, const std::string& robot_id) {
  scan_t msg;
  msg.utime = sweep.stamp_ns / 1000;
  const float remainder_s = static_cast<float>(sweep.stamp_ns - msg.utime * 1000) * 1e-9f;
  msg.robot_id = robot_id;
  msg.seq = sweep.seq;
  msg.num_points = static_cast<std::int32_t>(sweep.size());
  wire::pointsToRows(sweep.points, msg.xyz);
  msg.num_intensities = static_cast<std::int32_t>(sweep.intensity.size());
  msg.intensity = sweep.intensity;
  msg.num_labels = 0;
  msg.num_times = static_cast<std::int32_t>(sweep.time.size());
  msg.time = sweep.time;
  for (float& t : msg.time) t += remainder_s;
  return msg;
}

std::int64_t sweepEndUtime(const sensors::SensorScan& sweep) {
  const float last =
      sweep.time.empty() ? 0.0f : *std::max_element(sweep.time.begin(), sweep.time.end());
  return (sweep.stamp_ns + static_cast<std::int64_t>(static_cast<double>(last) * 1e9)) / 1000;
}

}  // namespace socc::tools
