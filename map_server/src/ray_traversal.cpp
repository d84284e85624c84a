#include "socc/map/ray_traversal.hpp"

namespace socc::map {

void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out) {
  forEachVoxelOnRay(from, to, voxel_size, [&out](const VoxelIndex& v) { out.push_back(v); });
}

}  // namespace socc::map
