#include "socc/odom/deskew.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace socc::odom {
namespace {

// The sweep's motion is evaluated exactly at kKnots + 1 instants and interpolated linearly in
// between: the interpolation error is second order in the knot spacing (below 1e-6 of the
// motion per sweep), and a scan costs a few multiply-adds per point instead of an SE(3) exp.
constexpr int kKnots = 256;

}  // namespace

LabeledCloud deskew(const LabeledCloud& cloud, const Vector6d& twist, double reference_time) {
  LabeledCloud out = cloud;
  if (!cloud.hasTimes() || twist.isZero(0.0)) return out;
  const auto [lo, hi] = std::minmax_element(cloud.times.begin(), cloud.times.end());
  const double t0 = *lo;
  const double step = std::max(static_cast<double>(*hi) - t0, 1e-9) / kKnots;
  std::vector<Eigen::Matrix<double, 3, 4>> knots(kKnots + 1);
  for (int k = 0; k <= kKnots; ++k)
    knots[k] = expSe3((t0 + k * step - reference_time) * twist).matrix().topRows<3>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cloud.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const double u = (cloud.times[i] - t0) / step;
      const int k = std::clamp(static_cast<int>(u), 0, kKnots - 1);
      const double f = u - k;
      const Eigen::Matrix<double, 3, 4> m = (1.0 - f) * knots[k] + f * knots[k + 1];
      out.points[i] = (m.leftCols<3>() * cloud.points[i].cast<double>() + m.col(3)).cast<float>();
    }
  });
  return out;
}

double sweepMidTime(const LabeledCloud& cloud) {
  if (!cloud.hasTimes()) return 0.0;
  const auto [lo, hi] = std::minmax_element(cloud.times.begin(), cloud.times.end());
  return 0.5 * (static_cast<double>(*lo) + static_cast<double>(*hi));
}

}  // namespace socc::odom
