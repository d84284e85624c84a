#include "sweep_builder.hpp"

#include <algorithm>

namespace socc::sensors {

void SweepBuilder::reserve(std::size_t points) {
  if (points <= times_ns_.size()) return;
  points_.resize(points);
  intensity_.resize(points);
  times_ns_.resize(points);
  ring_.resize(points);
  return_index_.resize(points);
}

void SweepBuilder::finish(bool complete, std::int64_t clock_offset_ns, std::vector<SensorScan>& out,
                          DecodeStats& stats) {
  const std::size_t n = n_;
  n_ = 0;
  clock_offset_ns_.reset();
  if (n == 0 || !(complete || keep_partial_)) return;
  const auto end = static_cast<std::ptrdiff_t>(n);
  const std::int64_t stamp = *std::min_element(times_ns_.begin(), times_ns_.begin() + end);
  SensorScan scan;
  scan.points.assign(points_.begin(), points_.begin() + end);
  scan.intensity.assign(intensity_.begin(), intensity_.begin() + end);
  scan.ring.assign(ring_.begin(), ring_.begin() + end);
  scan.return_index.assign(return_index_.begin(), return_index_.begin() + end);
  scan.time.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    scan.time[i] = static_cast<float>(static_cast<double>(times_ns_[i] - stamp) * 1e-9);
  scan.stamp_ns = stamp + clock_offset_ns;
  scan.complete = complete;
  scan.seq = next_seq_++;
  out.push_back(std::move(scan));
  ++stats.scans;
  if (!complete) ++stats.partial_scans;
}

}  // namespace socc::sensors
