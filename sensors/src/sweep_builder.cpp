#include "sweep_builder.hpp"

#include <algorithm>

namespace socc::sensors {

void SweepBuilder::reserve(std::size_t points) {
  scan_.points.reserve(points);
  scan_.intensity.reserve(points);
  scan_.ring.reserve(points);
  scan_.return_index.reserve(points);
  times_ns_.reserve(points);
}

void SweepBuilder::finish(bool complete, std::int64_t clock_offset_ns, std::vector<SensorScan>& out,
                          DecodeStats& stats) {
  const bool whole = complete && complete_;
  if (!scan_.points.empty() && (whole || keep_partial_)) {
    const std::int64_t stamp = *std::min_element(times_ns_.begin(), times_ns_.end());
    scan_.stamp_ns = stamp + clock_offset_ns;
    scan_.time.resize(times_ns_.size());
    for (std::size_t i = 0; i < times_ns_.size(); ++i)
      scan_.time[i] = static_cast<float>(static_cast<double>(times_ns_[i] - stamp) * 1e-9);
    scan_.complete = whole;
    scan_.seq = next_seq_++;
    const std::size_t capacity = scan_.points.size();
    out.push_back(std::move(scan_));
    ++stats.scans;
    if (!whole) ++stats.partial_scans;
    scan_ = SensorScan{};
    times_ns_.clear();
    reserve(capacity);
  } else {
    scan_.points.clear();
    scan_.intensity.clear();
    scan_.ring.clear();
    scan_.return_index.clear();
    times_ns_.clear();
  }
  complete_ = true;
}

}  // namespace socc::sensors
