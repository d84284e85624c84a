#pragma once
// p_occ >= threshold without an exp per voxel: the log-odds against logit(threshold); a voxel
// within rounding of that boundary is decided by its probability, as the threshold is defined.
// Shared by the chunk query and the view's block listing, so both see the same voxels.
#include <cmath>
#include <limits>

#include "socc/map/semantic_voxel.hpp"

namespace socc::map {

class OccupiedTest {
 public:
  explicit OccupiedTest(double threshold) : threshold_(threshold) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    logit_ = threshold <= 0.0   ? -kInf
             : threshold >= 1.0 ? kInf
                                : std::log(threshold / (1.0 - threshold));
  }
  bool operator()(float log_odds) const {
    if (log_odds > logit_ + kMargin) return true;
    if (log_odds < logit_ - kMargin) return false;
    return probability(log_odds) >= threshold_;
  }

 private:
  static constexpr double kMargin = 1e-6;
  double threshold_;
  double logit_;
};

}  // namespace socc::map
