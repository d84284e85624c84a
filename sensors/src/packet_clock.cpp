#include "packet_clock.hpp"

#include <algorithm>
#include <cmath>

namespace socc::sensors {

PacketClock::Placement PacketClock::place(std::uint32_t sensor_us, std::int64_t arrival_ns,
                                          double span_end_us) {
  const auto wrap_ns = static_cast<std::int64_t>(wrap_us_ * 1000.0);
  const std::int64_t raw_ns = static_cast<std::int64_t>(sensor_us) * 1000;
  const auto span_ns = static_cast<std::int64_t>(span_end_us * 1000.0);
  Placement p;
  std::int64_t sensor_ns = raw_ns + wraps_ * wrap_ns;
  if (started_) {
    std::int64_t delta = sensor_ns - last_sensor_ns_;
    if (delta < -wrap_ns / 2) {  // the stamp wrapped (top of the hour)
      ++wraps_;
      sensor_ns += wrap_ns;
      delta += wrap_ns;
    } else if (delta > wrap_ns / 2) {  // a late packet from before the wrap
      p.order = Order::kLate;
      return p;
    }
    if (delta <= 0) {
      p.order = Order::kLate;
      return p;
    }
    if (delta > 1'000'000'000) {
      p.order = Order::kRestart;
    } else {
      p.order = Order::kNext;
    }
  }
  const std::int64_t candidate = arrival_ns - (sensor_ns + span_ns);
  if (!started_ || p.order == Order::kRestart) {
    offset_ns_ = candidate;
  } else if (candidate < offset_ns_) {
    offset_ns_ = candidate;
  } else if (p.order == Order::kNext) {
    // Follows a sensor clock that runs slow by up to 50 ppm; arrival jitter alone moves it less.
    const std::int64_t step = sensor_ns - last_sensor_ns_;
    offset_ns_ += std::min(candidate - offset_ns_, step / 20000);
  }
  started_ = true;
  last_sensor_ns_ = sensor_ns;
  p.sensor_ns = sensor_ns;
  return p;
}

}  // namespace socc::sensors
