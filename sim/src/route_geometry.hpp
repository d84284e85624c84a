#pragma once
// A recorded route as driven, for the road-height model and its report: horizontal arc length,
// direction of travel, the road's grade by the recorded attitude, and values resampled along the
// arc length.
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc::sim {

// Per pose: horizontal arc length, direction of travel (none while standing), the road's grade
// along it by the recorded attitude (the slope of the sensor's x-y plane) and the way the sensor
// faces (+1 forwards, -1 reversing: a sensor pitched against the road tilts the grade it gives
// by that sign).
struct RouteGeometry {
  std::vector<double> s;
  std::vector<std::optional<Eigen::Vector2d>> heading;
  std::vector<double> attitude_grade;
  std::vector<double> facing;
};

RouteGeometry routeGeometry(const Poses& poses);

/// The poses' heights.
std::vector<double> heightsOf(const Poses& poses);

/// value (one per pose, at arc lengths s) at the arc lengths 0, step, 2 step, ... (m samples).
std::vector<double> alongPath(const std::vector<double>& s, const std::vector<double>& value,
                              double step, std::size_t m);

/// Where arc length s falls among `size` (>= 2) samples taken every step metres: the sample
/// before it (never the last) and the fraction of the way to the next; clamped to the samples.
struct SampleBracket {
  std::size_t before;
  double fraction;
};
SampleBracket bracketOf(std::size_t size, double step, double s);

/// u (sampled every step metres of arc length, >= 2 samples) at arc length s, linearly
/// interpolated.
double sampleAt(const std::vector<double>& u, double step, double s);

}  // namespace socc::sim
