#include "socc/odom/deskew.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace socc::odom {
namespace {

// Knot intervals over the sweep (SweepMotion): a scan costs a few multiply-adds per point
// instead of an SE(3) exp.
constexpr int kKnots = 256;

}  // namespace

SweepMotion::SweepMotion(const LabeledCloud& cloud, const Vector6d& twist, double reference_time) {
  if (!cloud.hasTimes() || twist.isZero(0.0)) return;
  const auto [lo, hi] = std::minmax_element(cloud.times.begin(), cloud.times.end());
  t0_ = *lo;
  step_ = std::max(static_cast<double>(*hi) - t0_, 1e-9) / kKnots;
  knots_.resize(kKnots + 1);
  for (int k = 0; k <= kKnots; ++k)
    knots_[k] = expSe3((t0_ + k * step_ - reference_time) * twist).matrix().topRows<3>();
}

Eigen::Vector3f SweepMotion::operator()(const Eigen::Vector3f& p, float time) const {
  const double u = (time - t0_) / step_;
  const int k = std::clamp(static_cast<int>(u), 0, kKnots - 1);
  const double f = u - k;
  const Eigen::Matrix<double, 3, 4> m = (1.0 - f) * knots_[k] + f * knots_[k + 1];
  return (m.leftCols<3>() * p.cast<double>() + m.col(3)).cast<float>();
}

LabeledCloud deskew(const LabeledCloud& cloud, const Vector6d& twist, double reference_time) {
  LabeledCloud out = cloud;
  const SweepMotion motion(cloud, twist, reference_time);
  if (motion.identity()) return out;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cloud.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      out.points[i] = motion(cloud.points[i], cloud.times[i]);
  });
  return out;
}

double sweepMidTime(const LabeledCloud& cloud) {
  if (!cloud.hasTimes()) return 0.0;
  const auto [lo, hi] = std::minmax_element(cloud.times.begin(), cloud.times.end());
  return 0.5 * (static_cast<double>(*lo) + static_cast<double>(*hi));
}

}  // namespace socc::odom
