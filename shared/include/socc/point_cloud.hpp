#pragma once
// A (semantic) LiDAR scan in one frame: points, optional labels and per-point times.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace socc {

using Points = std::vector<Eigen::Vector3f>;

struct LabeledCloud {
  Points points;
  std::vector<std::uint8_t> labels;  // empty or one class id (0..K) per point
  std::vector<float> times;          // empty or one time per point [s, relative to the scan]

  std::size_t size() const { return points.size(); }
  bool hasLabels() const { return !labels.empty(); }
  bool hasTimes() const { return !times.empty(); }
  /// True when labels/times are either empty or sized like points.
  bool consistent() const {
    return (labels.empty() || labels.size() == points.size()) &&
           (times.empty() || times.size() == points.size());
  }
};

/// cloud moved into the frame pose maps it to (labels and times kept).
inline LabeledCloud transformed(LabeledCloud cloud, const Eigen::Isometry3d& pose) {
  for (auto& p : cloud.points) p = (pose * p.cast<double>()).cast<float>();
  return cloud;
}

}  // namespace socc
