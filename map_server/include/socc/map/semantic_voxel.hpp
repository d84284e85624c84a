#pragma once
// The SOCC voxel behaviour (paper, Sec. Radix): WHAT a voxel stores and HOW hits and misses
// update it. This is the one place to change for a new mapping behaviour; the grid
// container, the ray traversal and the scan integrator only call onHits() / onMiss().
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "socc/labels.hpp"
#include "socc/map/map_config.hpp"
#include "socc/voxel.hpp"

namespace socc::map {

/// Geometric and semantic statistics of one voxel (only voxels that were hit have them).
/// Floats keep the pool lean; merges are computed in double.
struct VoxelStats {
  std::array<float, 3> mean{};
  std::array<float, 6> m2{};  // sum of squared deviations: xx xy xz yy yz zz
  std::array<float, 3> first_point{};
  std::uint32_t count = 0;
  std::array<std::uint16_t, kNumClasses> class_prob{};  // p * 65535 (resolution 1.5e-5)
  std::uint8_t label = kUnlabeled;                      // argmax of class_prob
  bool has_semantics = false;                           // a labeled scan has hit the voxel

  static constexpr float kProbScale = 65535.0f;
  float prob(int cls) const { return static_cast<float>(class_prob[cls]) / kProbScale; }
  /// Sample covariance M2 / (n - 1); zero below two points.
  Eigen::Matrix3d covariance() const;
  Eigen::Vector3d meanVector() const { return {mean[0], mean[1], mean[2]}; }
};

/// The points one scan put into one voxel: their moments (socc/voxel.hpp) and label histogram.
struct FrameAggregate : PointMoments {
  std::array<std::uint32_t, kNumClasses> label_counts{};
  std::uint32_t labeled = 0;  // points that carried a label

  using PointMoments::add;
  void add(const Eigen::Vector3d& p, std::uint8_t label) {
    add(p);
    ++label_counts[label];
    ++labeled;
  }
};

/// Chan et al.'s parallel update: merges a frame aggregate into running float statistics.
void mergeStatistics(VoxelStats& stats, const FrameAggregate& frame);

class SemanticVoxelBehaviour {
 public:
  explicit SemanticVoxelBehaviour(const MapConfig& config);

  /// A scan hit the voxel with the points in frame: log-odds += l(p_hit) (clamped), statistics
  /// merged, class distribution updated by EMA (set to the frame's frequencies on the first
  /// labeled hit). stats is fresh (value-initialised) when the voxel had none.
  void onHits(float& log_odds, VoxelStats& stats, const FrameAggregate& frame) const;

  /// A ray passed through the voxel: log-odds += l(p_miss) of the voxel's class (clamped).
  /// Returns true when the voxel is now free and has statistics: the caller drops them.
  bool onMiss(float& log_odds, const VoxelStats* stats) const;

  /// Log-odds added by a miss for a voxel with these statistics (nullptr: none).
  float missLogOdds(const VoxelStats* stats) const;
  /// missLogOdds(&stats) as a small number a block can keep beside the voxel (1 default,
  /// 2 static, 3 moving; never 0), and the log-odds of a miss of that class.
  int missClass(const VoxelStats& stats) const;
  float classMissLogOdds(int miss_class) const { return class_miss_[miss_class]; }
  float hitLogOdds() const { return hit_; }
  bool isOccupied(float log_odds) const { return log_odds >= occupied_; }
  /// Occupied, or within rounding of the threshold: a chunk asked at the map's threshold may
  /// show the voxel (its test works in double).
  bool nearOccupied(float log_odds) const { return log_odds >= occupied_ - 1e-3f; }
  float clampMin() const { return min_; }
  float clampMax() const { return max_; }

 private:
  float hit_, miss_, miss_static_, miss_moving_, min_, max_, occupied_;
  std::array<float, 4> class_miss_;  // by missClass (0 unused)
  double alpha_;
  bool semantics_;
};

// Inline: called for every voxel a ray clears (the hot loop of integration).
inline float SemanticVoxelBehaviour::missLogOdds(const VoxelStats* stats) const {
  if (!semantics_ || stats == nullptr || !stats->has_semantics || stats->label == kUnlabeled)
    return miss_;
  return isPotentiallyMoving(stats->label) ? miss_moving_ : miss_static_;
}

inline int SemanticVoxelBehaviour::missClass(const VoxelStats& stats) const {
  if (!semantics_ || !stats.has_semantics || stats.label == kUnlabeled) return 1;
  return isPotentiallyMoving(stats.label) ? 3 : 2;
}

inline bool SemanticVoxelBehaviour::onMiss(float& log_odds, const VoxelStats* stats) const {
  log_odds = std::clamp(log_odds + missLogOdds(stats), min_, max_);
  return stats != nullptr && !isOccupied(log_odds);
}

inline double logit(double p) {
  return std::log(p / (1.0 - p));
}
inline double probability(double log_odds) {
  return 1.0 / (1.0 + std::exp(-log_odds));
}

}  // namespace socc::map
