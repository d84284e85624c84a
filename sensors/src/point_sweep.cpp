#include "point_sweep.hpp"

#include <algorithm>

namespace socc::sensors {

void PointSweep::add(const Eigen::Vector3f& point, float intensity, std::int64_t sensor_time_ns,
                     std::uint16_t ring, std::uint8_t return_index) {
  points_.push_back(point);
  intensity_.push_back(intensity);
  time_ns_.push_back(sensor_time_ns);
  ring_.push_back(ring);
  return_index_.push_back(return_index);
}

SensorScan PointSweep::take(bool complete, std::int64_t seq) {
  SensorScan scan;
  scan.seq = seq;
  scan.complete = complete;
  const std::int64_t earliest =
      time_ns_.empty() ? 0 : *std::min_element(time_ns_.begin(), time_ns_.end());
  scan.stamp_ns = earliest + clock_offset_ns_;
  scan.time.reserve(time_ns_.size());
  for (const std::int64_t t : time_ns_)
    scan.time.push_back(static_cast<float>(t - earliest) * 1e-9f);
  scan.points = std::move(points_);
  scan.intensity = std::move(intensity_);
  scan.ring = std::move(ring_);
  scan.return_index = std::move(return_index_);
  clear();
  // The next sweep will be about as large: no reallocations while it grows.
  const std::size_t n = scan.points.size();
  points_.reserve(n);
  intensity_.reserve(n);
  time_ns_.reserve(n);
  ring_.reserve(n);
  return_index_.reserve(n);
  return scan;
}

void PointSweep::clear() {
  points_.clear();
  intensity_.clear();
  time_ns_.clear();
  ring_.clear();
  return_index_.clear();
  clock_offset_ns_ = 0;
  has_offset_ = false;
}

}  // namespace socc::sensors
