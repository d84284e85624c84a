#pragma once
// The correction a robot is told after a rebuild (docs/consistency.md, "Map correction"): one
// rigid transform from its raw frame into the rebuilt grid. The grid around the robot is made of
// its recent keyframes at their optimized poses, so the correction is fitted to them, not taken
// from the last keyframe alone: that one ends the chain and is held by one odometry edge and at
// most a closure, the least constrained pose of the graph; a robot told its correction would
// then register against a grid that disagrees with it by that keyframe's own error (measured
// on the KITTI-00 shape: up to 0.55 m, as jumps in the robot's raw chain after a swap).
#include <Eigen/Geometry>
#include <vector>

namespace socc::consistency {

struct CorrectionSample {
  Eigen::Isometry3d raw;        // the keyframe's pose as the robot integrated it (raw frame)
  Eigen::Isometry3d optimized;  // its pose in the optimized graph
};

/// The rigid transform C with C * raw ~ optimized over the samples: the mean rotation of the
/// samples' corrections, and the translation that maps the raw positions' centroid onto the
/// optimized positions' centroid (a fit of positions alone would be blind to a rotation about
/// a straight path). Identity for no sample.
Eigen::Isometry3d fitCorrection(const std::vector<CorrectionSample>& samples);

}  // namespace socc::consistency
