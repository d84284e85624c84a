#pragma once
// Collects the points of one sweep with absolute times (any clock) and hands it out as a
// SensorScan on the recording's clock (times relative to its earliest point). Shared by the
// packet decoders; the decision where a sweep ends stays with each decoder (azimuth cut, lost
// packets). Points go into buffers kept from sweep to sweep and written by index (the decoders'
// inner loop); a finished sweep gets its own copy of them.
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
    if (n_ == times_ns_.size()) grow();
    points_[n_] = Eigen::Vector3f(x, y, z);
    intensity_[n_] = intensity;
    times_ns_[n_] = time_ns;
    ring_[n_] = ring;
    return_index_[n_] = return_index;
    ++n_;
  }
  /// Marks the sweep under construction as not covering a whole rotation.
  void markIncomplete() { complete_ = false; }
  bool empty() const { return n_ == 0; }
  std::size_t size() const { return n_; }

  /// Ends the sweep: appends it to out (if complete, or kept as partial) with its stamp moved by
  /// clock_offset_ns onto the recording's clock, and starts the next, which is complete unless
  /// marked otherwise. Empty sweeps are never handed out.
  void finish(bool complete, std::int64_t clock_offset_ns, std::vector<SensorScan>& out,
              DecodeStats& stats);
  /// Room for this many points without growing (e.g. a whole turn's worth).
  void reserve(std::size_t points);

 private:
  void grow() { reserve(times_ns_.empty() ? 4096 : 2 * times_ns_.size()); }

  bool keep_partial_;
  bool complete_ = true;
  // Sized to the capacity; the first n_ entries are the sweep's points.
  std::vector<Eigen::Vector3f> points_;
  std::vector<float> intensity_;
  std::vector<std::int64_t> times_ns_;
  std::vector<std::uint16_t> ring_;
  std::vector<std::uint8_t> return_index_;
  std::size_t n_ = 0;
  std::int64_t next_seq_ = 0;
};

}  // namespace socc::sensors
