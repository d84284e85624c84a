#pragma once
// Collects the points of one sweep with absolute times on the sensor's clock and hands it out as
// a SensorScan on the recording's clock (times relative to its earliest point). Every packet
// decoder (Velodyne, Ouster, Hesai) builds its sweeps with it; where a sweep ends stays with
// each decoder (azimuth cut, frame id, lost packets). Points go into buffers kept from sweep to
// sweep and written by index (the decoders' inner loop); a finished sweep gets its own copy.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

class SweepBuilder {
 public:
  /// keep_partial: incomplete sweeps are handed out (complete == false) instead of dropped.
  explicit SweepBuilder(bool keep_partial) : keep_partial_(keep_partial) {}

  void add(const Eigen::Vector3f& point, float intensity, std::int64_t time_ns, std::uint16_t ring,
           std::uint8_t return_index) {
    if (n_ == times_ns_.size()) grow();
    points_[n_] = point;
    intensity_[n_] = intensity;
    times_ns_[n_] = time_ns;
    ring_[n_] = ring;
    return_index_[n_] = return_index;
    ++n_;
  }
  bool empty() const { return n_ == 0; }
  std::size_t size() const { return n_; }

  /// recording clock - sensor clock for the sweep under construction, taken at its first packet:
  /// the first call after finish() sets it, later ones are ignored (Ouster, Hesai).
  void fixClockOffset(std::int64_t offset_ns) {
    if (!clock_offset_ns_) clock_offset_ns_ = offset_ns;
  }

  /// Ends the sweep: appends it to out (if complete, or kept as partial) with its stamp moved
  /// onto the recording's clock by clock_offset_ns, counts it in stats, and starts the next.
  /// Empty sweeps are never handed out.
  void finish(bool complete, std::int64_t clock_offset_ns, std::vector<SensorScan>& out,
              DecodeStats& stats);
  /// The same with the offset fixed by fixClockOffset (0 when none was).
  void finish(bool complete, std::vector<SensorScan>& out, DecodeStats& stats) {
    finish(complete, clock_offset_ns_.value_or(0), out, stats);
  }
  /// Room for this many points without growing (e.g. a whole turn's worth).
  void reserve(std::size_t points);

 private:
  void grow() { reserve(times_ns_.empty() ? 4096 : 2 * times_ns_.size()); }

  bool keep_partial_;
  // Sized to the capacity; the first n_ entries are the sweep's points.
  std::vector<Eigen::Vector3f> points_;
  std::vector<float> intensity_;
  std::vector<std::int64_t> times_ns_;
  std::vector<std::uint16_t> ring_;
  std::vector<std::uint8_t> return_index_;
  std::size_t n_ = 0;
  std::int64_t next_seq_ = 0;
  std::optional<std::int64_t> clock_offset_ns_;
};

/// recording clock - sensor clock for a packet captured at capture_ns whose newest
/// measurement is at sensor_ns; 0 when the transport gave no capture time.
inline std::int64_t clockOffset(std::int64_t capture_ns, std::int64_t sensor_ns) {
  return capture_ns == 0 ? 0 : capture_ns - sensor_ns;
}

}  // namespace socc::sensors
