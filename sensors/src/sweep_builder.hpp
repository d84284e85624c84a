#pragma once
// Collects the points of one sweep with absolute times (any clock) and hands it out as a
// SensorScan on the recording's clock (times relative to its earliest point). Shared by the packet
// decoders; the decision where a sweep ends stays with each decoder (azimuth cut, lost packets).
#include <cstdint>
#include <vector>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

class SweepBuilder {
 public:
  /// keep_partial: incomplete sweeps are handed out (complete == false) instead of dropped.
  explicit SweepBuilder(bool keep_partial) : keep_partial_(keep_partial) {}

  void add(float x, float y, float z, float intensity, std::int64_t time_ns, std::uint16_t ring,
           std::uint8_t return_index) {
    scan_.points.emplace_back(x, y, z);
    scan_.intensity.push_back(intensity);
    times_ns_.push_back(time_ns);
    scan_.ring.push_back(ring);
    scan_.return_index.push_back(return_index);
  }
  /// Marks the sweep under construction as not covering a whole rotation.
  void markIncomplete() { complete_ = false; }
  bool empty() const { return scan_.points.empty(); }
  std::size_t size() const { return scan_.points.size(); }
  /// Time of the sweep's first point, when it has one.
  std::int64_t firstTime() const { return times_ns_.empty() ? 0 : times_ns_.front(); }

  /// Ends the sweep: appends it to out (if complete, or kept as partial) with its stamp moved by
  /// clock_offset_ns onto the recording's clock, and starts the next, which is complete unless
  /// marked otherwise. Empty sweeps are never handed out.
  void finish(bool complete, std::int64_t clock_offset_ns, std::vector<SensorScan>& out,
              DecodeStats& stats);
  void reserve(std::size_t points);

 private:
  bool keep_partial_;
  bool complete_ = true;
  SensorScan scan_;
  std::vector<std::int64_t> times_ns_;
  std::int64_t next_seq_ = 0;
};

}  // namespace socc::sensors
