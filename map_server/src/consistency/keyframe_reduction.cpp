#include "keyframe_reduction.hpp"

#include "socc/odom/relocalization.hpp"

namespace socc::consistency {

ReducedScan reduceScan(const LabeledCloud& cloud, const ConsistencyParams& params) {
  ReducedScan out;
  LabeledCloud near;
  const float max2 = static_cast<float>(params.keyframe_range * params.keyframe_range);
  for (const Eigen::Vector3f& p : cloud.points)
    if (p.squaredNorm() <= max2) near.points.push_back(p);
  constexpr std::size_t kMaxPoints = 60'000;
  out.points = odom::localizationPoints(near, params.keyframe_voxel, kMaxPoints);
  if (params.correct_grid) out.scan = compactScan(cloud, params.rebuild_voxel);
  return out;
}

}  // namespace socc::consistency
