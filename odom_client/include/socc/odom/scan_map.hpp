#pragma once
// A LocalMap made directly from one cloud (no map server): voxels of voxel_size with the first
// point, the normal and planarity of socc/voxel.hpp (the map server's rule), p_occ = 1 and the
// majority label. Used for scan-to-scan reference registrations (tests, benchmarks, tools).
#include "socc/odom/local_map.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

LocalMap buildScanMap(const LabeledCloud& cloud, double voxel_size);

/// The voxels of buildScanMap, in the order of their first points in cloud.
std::vector<MapVoxel> scanVoxels(const LabeledCloud& cloud, double voxel_size);

}  // namespace socc::odom
