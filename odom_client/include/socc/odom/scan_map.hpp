#pragma once
// A LocalMap made directly from one cloud (no map server): voxels of voxel_size with the first
// point, the normal and planarity of socc/voxel.hpp (the map server's rule), the points' moments,
// p_occ = 1 and the majority label. Used for scan-to-scan reference registrations (tests,
// benchmarks, tools) and the pipelined target's own voxels.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "socc/labels.hpp"
#include "socc/odom/local_map.hpp"
#include "socc/point_cloud.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {

/// The points of one voxel of a cloud.
struct CloudVoxel {
  VoxelIndex key;
  PointMoments moments;  // in the cloud's order: first is the point the server keeps
  std::array<std::uint32_t, kNumClasses> labels{};
};

/// Asked once per voxel of a cloud, at its first point: false leaves the voxel out.
using KeepVoxel = std::function<bool(const VoxelIndex&)>;

/// The points of cloud (sensor frame, taken at pose), in the map frame, grouped by voxel of
/// voxel_size, in the order of each voxel's first point; only the voxels keep accepts (all
/// without it), whose points are then not summed.
std::vector<CloudVoxel> cloudVoxels(const LabeledCloud& cloud, const Eigen::Isometry3d& pose,
                                    double voxel_size, const KeepVoxel& keep = {});

/// The map voxel of a cloud's voxel (the moments kept below chunk::kMomentsBelow points), its
/// normal and planarity from solver.
MapVoxel toMapVoxel(const CloudVoxel& voxel, EigenSolver solver);

/// The voxels of several clouds (cloudVoxels of one voxel size), in order, merged into the voxels
/// of their concatenation: each keeps the first point of the first part that has it; the moments'
/// sums differ by rounding only.
std::vector<CloudVoxel> mergedVoxels(const std::vector<const std::vector<CloudVoxel>*>& parts);

/// The map of these voxels (their normals from the iterative solver, as buildScanMap's).
LocalMap buildVoxelMap(const std::vector<CloudVoxel>& voxels);

LocalMap buildScanMap(const LabeledCloud& cloud, double voxel_size);

/// The voxels of buildScanMap, in the order of their first points in cloud.
std::vector<MapVoxel> scanVoxels(const LabeledCloud& cloud, double voxel_size);

}  // namespace socc::odom
