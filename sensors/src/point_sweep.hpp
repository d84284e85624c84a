#pragma once
// The sweep a packet decoder is building: points with their absolute times on the sensor's
// clock, turned into a SensorScan (times relative to the earliest point, stamp on the
// recording's clock) when the sweep ends. Shared by the Ouster and Hesai decoders.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

class PointSweep {
 public:
  void add(const Eigen::Vector3f& point, float intensity, std::int64_t sensor_time_ns,
           std::uint16_t ring, std::uint8_t return_index);
  /// recording clock - sensor clock [ns], fixed at the sweep's first packet (0: unknown).
  void setClockOffset(std::int64_t offset_ns) { clock_offset_ns_ = offset_ns; }
  bool hasClockOffset() const { return has_offset_; }
  void markClockOffset() { has_offset_ = true; }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  /// The scan (times relative to its earliest point); the sweep is empty afterwards.
  SensorScan take(bool complete, std::int64_t seq);
  void clear();

 private:
  std::vector<Eigen::Vector3f> points_;
  std::vector<float> intensity_;
  std::vector<std::int64_t> time_ns_;
  std::vector<std::uint16_t> ring_;
  std::vector<std::uint8_t> return_index_;
  std::int64_t clock_offset_ns_ = 0;
  bool has_offset_ = false;
};

/// recording clock - sensor clock for a packet captured at capture_ns whose newest
/// measurement is at sensor_ns; 0 when the transport gave no capture time.
inline std::int64_t clockOffset(std::int64_t capture_ns, std::int64_t sensor_ns) {
  return capture_ns == 0 ? 0 : capture_ns - sensor_ns;
}

}  // namespace socc::sensors
