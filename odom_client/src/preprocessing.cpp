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

void dropLabels(LabeledCloud& cloud) {
  for (std::uint8_t& label : cloud.labels) label = kUnlabeled;
}

}  // namespace socc::odom
