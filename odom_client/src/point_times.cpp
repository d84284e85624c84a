#include "socc/odom/point_times.hpp"

#include <cmath>

namespace socc::odom {

std::vector<float> azimuthTimes(const Points& points, const SweepGeometry& sweep) {
  constexpr double kTwoPi = 2.0 * M_PI;
  const double start = sweep.start_azimuth_deg * M_PI / 180.0;
  const double direction = sweep.clockwise ? -1.0 : 1.0;
  std::vector<float> times(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double azimuth = std::atan2(points[i].y(), points[i].x());
    double turned = std::fmod(direction * (azimuth - start), kTwoPi);  // angle swept so far
    if (turned < 0.0) turned += kTwoPi;
    if (turned > kTwoPi - 1e-6) turned = 0.0;  // the start azimuth itself, up to float rounding
    times[i] = static_cast<float>((turned / kTwoPi - sweep.scan_time_in_sweep) * sweep.period);
  }
  return times;
}

}  // namespace socc::odom
