#pragma once
// Puts packets on the recording's clock. A LiDAR stamps each packet with its own clock
// (Velodyne: microseconds past the hour, from GPS/PTP or free-running); the transport stamps it
// on arrival (pcap record, socket, bag message). Point times come from the sensor's stamps (exact
// firing times); the offset to the recording's clock is the smallest arrival delay seen so far
// (the transport only adds latency). Decoders keep a sweep's times on the sensor's clock and add
// the offset once, when the sweep is handed out, so times within a sweep keep their exact spacing.
#include <cstdint>
#include <optional>

namespace socc::sensors {

class PacketClock {
 public:
  /// wrap_us: period of the sensor stamp (one hour for Velodyne).
  explicit PacketClock(double wrap_us) : wrap_us_(wrap_us) {}

  enum class Order { kFirst, kNext, kLate, kRestart };
  struct Placement {
    Order order = Order::kFirst;
    std::int64_t sensor_ns = 0;  // the sensor stamp, unwrapped [ns, the sensor's clock]
  };

  /// Places a packet with sensor stamp sensor_us and arrival time arrival_ns whose last firing
  /// is span_end_us after its stamp. kLate: older than the last packet (skip it). kRestart: a
  /// jump of more than a second (recording paused, sensor restarted): a new stream.
  Placement place(std::uint32_t sensor_us, std::int64_t arrival_ns, double span_end_us);
  /// Recording clock - sensor clock [ns]: the best estimate so far.
  std::int64_t offsetNs() const { return offset_ns_; }

 private:
  double wrap_us_;
  bool started_ = false;
  std::int64_t wraps_ = 0;
  std::int64_t last_sensor_ns_ = 0;  // unwrapped
  std::int64_t offset_ns_ = 0;       // recording clock - sensor clock
};

}  // namespace socc::sensors
