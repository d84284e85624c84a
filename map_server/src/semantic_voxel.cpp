#include "socc/map/semantic_voxel.hpp"

#include <algorithm>

#include "socc/rounding.hpp"

namespace socc::map {

Eigen::Matrix3d VoxelStats::covariance() const {
  Eigen::Matrix3d m;
  m << m2[0], m2[1], m2[2],  //
      m2[1], m2[3], m2[4],   //
      m2[2], m2[4], m2[5];
  return sampleCovariance(m, count);
}

void mergeStatistics(VoxelStats& stats, const FrameAggregate& frame) {
  if (frame.count == 0) return;
  const Eigen::Vector3d mean_b = frame.mean();
  const Eigen::Matrix3d mb = frame.m2();
  if (stats.count == 0) {
    for (int i = 0; i < 3; ++i) stats.mean[i] = static_cast<float>(mean_b[i]);
    stats.m2 = {static_cast<float>(mb(0, 0)), static_cast<float>(mb(0, 1)),
                static_cast<float>(mb(0, 2)), static_cast<float>(mb(1, 1)),
                static_cast<float>(mb(1, 2)), static_cast<float>(mb(2, 2))};
    stats.first_point = {static_cast<float>(frame.first.x()), static_cast<float>(frame.first.y()),
                         static_cast<float>(frame.first.z())};
    stats.count = frame.count;
    return;
  }
  const double na = stats.count;
  const double nb = frame.count;
  const double n = na + nb;
  const Eigen::Vector3d mean_a = stats.meanVector();
  const Eigen::Vector3d delta = mean_b - mean_a;
  const Eigen::Vector3d mean = mean_a + delta * (nb / n);
  const Eigen::Matrix3d corr = delta * delta.transpose() * (na * nb / n);
  const int idx[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int k = 0; k < 6; ++k) {
    const int r = idx[k][0], c = idx[k][1];
    stats.m2[k] = static_cast<float>(stats.m2[k] + mb(r, c) + corr(r, c));
  }
  for (int i = 0; i < 3; ++i) stats.mean[i] = static_cast<float>(mean[i]);
  stats.count += frame.count;
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
