#pragma once
// The time between scans as the input's time stamps show it: the median of the last few stamp
// differences. A dropped scan or a paused recording is then a gap of several periods (its
// prediction and threshold scale with it), not a new period.
#include <deque>

namespace socc::odom {

class FramePeriod {
 public:
  /// assumed [s]: the period until the first stamp difference (config frame_period).
  explicit FramePeriod(double assumed) : assumed_(assumed) {}

  /// One stamp difference [s]; non-positive ones (repeated stamps) are ignored.
  void add(double dt);
  /// [s] the median of the recent differences, or the assumed period before any.
  double period() const;
  /// How many periods dt spans, at least 1 (1: the next scan on time; 6: five dropped).
  double periods(double dt) const;

 private:
  static constexpr std::size_t kRecent = 9;
  double assumed_;
  std::deque<double> recent_;
};

}  // namespace socc::odom
