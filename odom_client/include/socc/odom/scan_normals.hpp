#pragma once
// Surface normals of a (downsampled) scan from its own points. A map voxel of fewer than 5
// points has no known geometry; pairing a scan point with its first point aligns the sensor's
// sampling pattern (its rings) with the one that made the map, which on a young map of a sparse
// sensor means "standing still". Where the scan itself shows a surface, the pair is taken along
// that surface's normal instead (registration.hpp).
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::odom {

/// Per point: the unit normal of the plane through its nearest neighbours within radius (at
/// least 5, planarity below planarity_threshold, spread over a surface rather than along one
/// ring's line); zero where the neighbourhood is no such plane.
Points scanNormals(const Points& points, double radius, double planarity_threshold);

}  // namespace socc::odom
