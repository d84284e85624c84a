#include "socc/map/semantic_voxel.hpp"

#include <algorithm>

#include "socc/rounding.hpp"

namespace socc::map {

Eigen::Matrix3d VoxelStats::covariance() const {
  return sampleCovariance(symmetricOf(m2), count);
}

void mergeStatistics(VoxelStats& stats, const FrameAggregate& frame) {
  if (frame.count == 0) return;
  if (stats.count == 0)
    stats.first_point = {static_cast<float>(frame.first.x()), static_cast<float>(frame.first.y()),
                         static_cast<float>(frame.first.z())};
  mergeMoments(stats.count, stats.mean, stats.m2, frame);
}

SemanticVoxelBehaviour::SemanticVoxelBehaviour(const MapConfig& c)
    : hit_(static_cast<float>(logit(c.p_hit))),
      miss_(static_cast<float>(logit(c.p_miss))),
      miss_static_(static_cast<float>(logit(c.p_miss_static))),
      miss_moving_(static_cast<float>(logit(c.p_miss_moving))),
      min_(static_cast<float>(logit(c.clamp_min))),
      max_(static_cast<float>(logit(c.clamp_max))),
      occupied_(static_cast<float>(logit(c.occupancy_threshold))),
      class_miss_{miss_, miss_, miss_static_, miss_moving_},
      alpha_(c.ema_alpha),
      semantics_(c.semantics) {}

void SemanticVoxelBehaviour::onHits(float& log_odds, VoxelStats& stats,
                                    const FrameAggregate& frame) const {
  log_odds = std::clamp(log_odds + hit_, min_, max_);
  mergeStatistics(stats, frame);
  if (frame.labeled == 0) return;  // an unlabeled scan carries no semantic evidence

  // EMA of the class distribution with the frame's label frequencies. The first labeled hit
  // adopts the frequencies, so the distribution always sums to one.
  const double keep = stats.has_semantics ? alpha_ : 0.0;
  const double inv_n = 1.0 / static_cast<double>(frame.labeled);
  int best = 0;
  for (int k = 0; k < kNumClasses; ++k) {
    // A class with no probability that the frame did not see stays at exactly 0 (0 * keep +
    // 0 * (1 - keep) rounds to 0) and cannot become the argmax (> is strict): skipped, which
    // leaves the arithmetic of the others unchanged (most voxels see one or two classes).
    if (frame.label_counts[k] == 0 && stats.class_prob[k] == 0) continue;
    const double p_hat = frame.label_counts[k] * inv_n;
    const double p = keep * stats.prob(k) + (1.0 - keep) * p_hat;
    stats.class_prob[k] =
        static_cast<std::uint16_t>(roundHalfAway(std::clamp(p, 0.0, 1.0) * VoxelStats::kProbScale));
    if (stats.class_prob[k] > stats.class_prob[best]) best = k;
  }
  stats.label = static_cast<std::uint8_t>(best);
  stats.has_semantics = true;
}

}  // namespace socc::map
