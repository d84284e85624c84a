#pragma once
// A robot's trajectory revised by the pose graph (docs/consistency.md, "The revised
// trajectory"): the consistency service optimizes only its keyframes; every output pose between
// two keyframes moves with the revisions of both, interpolated by seq.
//
// Output poses may jump at map corrections (the client moves its frame by the correction the
// server tells it, docs/consistency.md item 13). The revision is interpolated in the robot's
// first frame, where its chain has no jump: each output pose is taken back by the corrections
// applied at or before its seq, so the frames between two keyframes on either side of a
// correction are not smeared across it.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc {

/// A keyframe's optimized pose (map_T_sensor), by the seq of its INTEGRATE.
struct KeyframeEstimate {
  std::int64_t seq = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// A map correction the robot applied: output poses with seq >= from_seq are correction x what
/// they were before it (several compose in order).
struct FrameCorrection {
  std::int64_t from_seq = 0;
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
};

struct RevisedTrajectory {
  Poses poses;             // one per output pose, in its order
  int keyframes = 0;       // keyframes matched to an output pose (the others are skipped)
  double max_shift = 0.0;  // [m] the largest translation any pose moved
};

/// Revises output poses (seqs[i] with poses[i], seqs increasing) by the keyframes' optimized
/// poses: keyframe j at output pose P_j gets D_j = optimized_j x P_j^-1 (in the first frame);
/// poses between two keyframes get D interpolated by seq (translation linearly, rotation by
/// slerp); before the first and after the last keyframe the nearest D. A keyframe whose seq is
/// not among seqs is skipped. No keyframe matched: the poses unchanged. Throws
/// std::invalid_argument when seqs and poses differ in size or seqs do not increase.
RevisedTrajectory reviseTrajectory(const std::vector<std::int64_t>& seqs, const Poses& poses,
                                   const std::vector<KeyframeEstimate>& keyframes,
                                   const std::vector<FrameCorrection>& corrections = {});

}  // namespace socc
