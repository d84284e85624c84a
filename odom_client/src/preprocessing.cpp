#include "socc/odom/preprocessing.hpp"

#include <cmath>

#include "socc/labels.hpp"

namespace socc::odom {

std::string checkCloud(const LabeledCloud& cloud) {
  if (!cloud.consistent())
    return "labels/times count differs from the point count (" +
           std::to_string(cloud.points.size()) + " points, " + std::to_string(cloud.labels.size()) +
           " labels, " + std::to_string(cloud.times.size()) + " times)";
  for (const std::uint8_t label : cloud.labels)
    if (!isValidClass(label)) return "label " + std::to_string(label) + " is not a class id 0..19";
  return {};
}

LabeledCloud rangeFilter(const LabeledCloud& cloud, double min_range, double max_range) {
  LabeledCloud out;
  out.points.reserve(cloud.size());
  if (cloud.hasLabels()) out.labels.reserve(cloud.size());
  if (cloud.hasTimes()) out.times.reserve(cloud.size());
  const double min2 = min_range * min_range;
  const double max2 = max_range * max_range;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& p = cloud.points[i];
    if (!p.allFinite() || (cloud.hasTimes() && !std::isfinite(cloud.times[i]))) continue;
    const double r2 = p.cast<double>().squaredNorm();
    if (r2 < min2 || r2 > max2) continue;
    out.points.push_back(p);
    if (cloud.hasLabels()) out.labels.push_back(cloud.labels[i]);
    if (cloud.hasTimes()) out.times.push_back(cloud.times[i]);
  }
  return out;
}

void correctElevation(LabeledCloud& cloud, double radians) {
  if (radians == 0.0) return;
  const double c = std::cos(radians), s = std::sin(radians);
  for (Eigen::Vector3f& p : cloud.points) {
    // Rotation by `radians` in the vertical plane through the point: horizontal distance h and
    // height z turn like a 2-D vector, the azimuth stays.
    const double x = p.x(), y = p.y(), z = p.z();
    const double h = std::hypot(x, y);
    if (h == 0.0) continue;  // straight up or down: no azimuth to keep
    const double h2 = c * h - s * z;
    const double scale = h2 / h;
    p = Eigen::Vector3f(static_cast<float>(x * scale), static_cast<float>(y * scale),
                        static_cast<float>(s * h + c * z));
  }
}

void dropLabels(LabeledCloud& cloud) {
  for (std::uint8_t& label : cloud.labels) label = kUnlabeled;
}

}  // namespace socc::odom
