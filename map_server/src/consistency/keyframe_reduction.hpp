#pragma once
// What the consistency service keeps of a keyframe's cloud (docs/consistency.md, "How it
// works"): the points it matches with and, with correct_grid, the scan the grid is rebuilt from.
// The worker reduces each cloud it takes; the map's thread reduces a keyframe's cloud on arrival
// instead when max_pending_scans full clouds already wait, so that no keyframe loses its scan
// and the queue's memory stays bounded per keyframe.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "consistency_params.hpp"
#include "keyframe_scan.hpp"
#include "socc/point_cloud.hpp"

namespace socc::consistency {

struct ReducedScan {
  std::vector<Eigen::Vector3f> points;  // sensor frame, keyframe_range, keyframe_voxel grid
  KeyframeScan scan;                    // rebuild_voxel grid with labels (empty: !correct_grid)

  std::size_t bytes() const {
    return sizeof(ReducedScan) + points.capacity() * sizeof(Eigen::Vector3f) + scan.bytes();
  }
};

/// cloud (sensor frame) as the keyframe keeps it.
ReducedScan reduceScan(const LabeledCloud& cloud, const ConsistencyParams& params);

}  // namespace socc::consistency
