#pragma once
// Correspondence weights of SOCC-ICP (paper Sec. semantic-assisted data association):
// w = w_gm * w_occ * w_sem, each in [0, 1].
#include <array>
#include <cmath>
#include <cstdint>

namespace socc::odom {

/// Geman-McClure weight as KISS-ICP: k^2 / (k + r^2)^2 with kernel scale k (= sigma / 3) and
/// squared residual r^2; 1 at r = 0, decreasing towards 0.
inline double gemanMcClureWeight(double squared_residual, double kernel) {
  const double d = kernel + squared_residual;
  return (kernel * kernel) / (d * d);
}

/// w_occ = p_occ^gamma.
inline double occupancyWeight(double p_occ, double gamma) {
  return std::pow(p_occ, gamma);
}

/// w_occ of many voxels at one gamma. A chunk's occupancies are bytes (p = b / 255): their
/// weights come from a table, bit for bit occupancyWeight's, instead of a pow each; any other p
/// (an overlay voxel's p_hit) is computed.
class OccupancyWeights {
 public:
  explicit OccupancyWeights(double gamma) : gamma_(gamma) {
    for (int b = 0; b < 256; ++b) table_[b] = occupancyWeight(static_cast<float>(b) / 255.f, gamma);
  }
  double operator()(float p_occ) const {
    if (p_occ >= 0.f && p_occ <= 1.f) {
      const auto b = static_cast<int>(p_occ * 255.f + 0.5f);
      if (static_cast<float>(b) / 255.f == p_occ) return table_[b];
    }
    return occupancyWeight(p_occ, gamma_);
  }

 private:
  double gamma_;
  std::array<double, 256> table_{};
};

/// Labels match when equal or when either is 0 (unlabeled).
inline bool labelsMatch(std::uint8_t point_label, std::uint8_t voxel_label) {
  return point_label == voxel_label || point_label == 0 || voxel_label == 0;
}

/// w_sem = w_lower + match * (1 - w_lower) * p_label between two labels; 1 (neutral) when either
/// side is unlabeled: no semantic evidence is no reason to down-weight a correspondence, so an
/// unlabeled robot registers exactly as with semantics off, and robots with and without labels
/// can share one map without biasing each other.
inline double semanticWeight(std::uint8_t point_label, std::uint8_t voxel_label, double p_label,
                             double w_lower) {
  if (point_label == 0 || voxel_label == 0) return 1.0;
  const double match = labelsMatch(point_label, voxel_label) ? 1.0 : 0.0;
  return w_lower + match * (1.0 - w_lower) * p_label;
}

}  // namespace socc::odom
