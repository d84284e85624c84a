#pragma once
// What integrating one of the robot's own frames does to its registration target, worked out by
// the client while the frame's Integrate travels (the pipelined target, map_pipeline.hpp): the
// voxels the frame adds, and its points merged into the voxels of few points as the map server
// merges them.
#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "socc/odom/local_map.hpp"
#include "socc/odom/scan_map.hpp"
#include "socc/point_cloud.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {

/// A frame's voxels against a map's (splitFrame).
struct FrameSplit {
  std::vector<CloudVoxel> outside;  // the voxels the map lacks: those the frame adds
  // The frame's points in each voxel of the map that came with moments, by voxel id in the order
  // of their first points: what integrating the frame merges into them.
  std::vector<std::pair<std::size_t, PointMoments>> into_known;
};

/// The voxels of cloud (sensor frame, taken at pose) on map's voxel grid. map must be made from
/// a chunk (its voxel size); throws std::logic_error otherwise.
FrameSplit splitFrame(const LocalMap& map, const LabeledCloud& cloud,
                      const Eigen::Isometry3d& pose);

/// v after a frame's points in it are merged as the map server merges them: its moments grow
/// (and are dropped from chunk::kMomentsBelow points on, as a chunk drops them), its normal and
/// planarity follow them from 5 points on (the server's closed form); the occupancy and label
/// stay (a stand-in until the next chunk). v as it is when it has no moments.
MapVoxel withPoints(MapVoxel v, const PointMoments& points);

/// Adds a frame (cloud in the sensor frame, taken at pose) to a pipelined target: base is the
/// target (its first chunk_size voxels its chunk's), overlay the voxels after them, updated its
/// chunk voxels replaced since. The frame's new voxels are appended to overlay (p_occ of a hit
/// once), its points merged into the voxels with moments (withPoints).
void addFrame(const LocalMap& base, std::size_t chunk_size, const LabeledCloud& cloud,
              const Eigen::Isometry3d& pose, std::vector<MapVoxel>& overlay, VoxelUpdates& updated);

}  // namespace socc::odom
