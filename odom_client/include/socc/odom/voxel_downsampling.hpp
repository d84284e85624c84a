#pragma once
// Semantic-aware voxel downsampling (paper Sec. semantic-aware downsampling): each class c is
// voxelised separately with voxel size alpha_c * v_adapt and every voxel is replaced by the MEAN of
// its points (a downsampling, not a subsampling). alpha_c = 0 removes the class.
#include <array>

#include "socc/labels.hpp"
#include "socc/odom/deskew.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

/// The output has one label per point (0 when the input had none) and, when the input has
/// times, each voxel's mean time (what a continuous-time registration needs of the sweep).
/// With a motion, the points are deskewed by it first: the result of downsampling
/// deskew(cloud, ...), without the deskewed copy of the whole cloud.
LabeledCloud semanticVoxelDownsample(const LabeledCloud& cloud, double voxel_size,
                                     const std::array<double, kNumClasses>& class_factor,
                                     const SweepMotion* motion = nullptr);

/// Adapts v_adapt from frame to frame so that about target points survive downsampling:
/// on a surface the count scales like 1/v^2, so v *= sqrt(count / target), with the step
/// limited to [0.5, 2] and v kept within [min_size, max_size].
class AdaptiveVoxelSize {
 public:
  AdaptiveVoxelSize(double initial, double min_size, double max_size, int target);
  double size() const { return size_; }
  /// Feeds the number of points the current size produced.
  void update(std::size_t count);
  /// True when count is so far from the target that the frame should be redone.
  bool farOff(std::size_t count) const;

 private:
  double size_;
  double min_size_;
  double max_size_;
  int target_;
};

}  // namespace socc::odom
