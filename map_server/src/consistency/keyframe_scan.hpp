#pragma once
// What the consistency service keeps of a keyframe to rebuild the grid (docs/consistency.md,
// "Map correction"): the scan in the sensor frame, downsampled per class to a grid fine enough
// that every 0.5 m map voxel still gets the points its statistics (mean, covariance, normal)
// need, stored as integrate_request_t stores points (int16, 6 bytes a point) plus one label.
#include <cstdint>
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::consistency {

struct KeyframeScan {
  float resolution = 0.f;                      // [m] per unit of xyz
  std::vector<std::vector<std::int16_t>> xyz;  // [axis][point], sensor frame
  std::vector<std::uint8_t> labels;            // one per point

  bool empty() const { return labels.empty(); }
  std::size_t size() const { return labels.size(); }
  std::size_t bytes() const;
  /// The points (labels, no times) as the map integrates them.
  LabeledCloud cloud() const;
};

/// cloud (sensor frame) downsampled per class to voxel (each voxel's mean point, its label).
KeyframeScan compactScan(const LabeledCloud& cloud, double voxel);

}  // namespace socc::consistency
