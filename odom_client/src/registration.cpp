#include "socc/odom/registration.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cmath>
#include <deque>

#include "socc/odom/se3.hpp"
#include "socc/odom/weights.hpp"

namespace socc::odom {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Normal equations of one residual type (left-perturbation Jacobians in the map frame).
struct System {
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  int count = 0;
  double squared_residuals = 0.0;  // unweighted, for the health check
  System& operator+=(const System& o) {
    H += o.H;
    b += o.b;
    count += o.count;
    squared_residuals += o.squared_residuals;
    return *this;
  }
};

struct Systems {
  System planar;
  System point;
  Systems& operator+=(const Systems& o) {
    planar += o.planar;
    point += o.point;
    return *this;
  }
};

void accumulate(const Eigen::Vector3d& p, const MapVoxel& v, const Correspondence& c,
                Systems& out) {
  if (c.planar) {
    // e = n . (p - q);  de/d(rho, phi) = [n^T, (p x n)^T]
    Vector6d J;
    J.head<3>() = v.normal;
    J.tail<3>() = p.cross(v.normal);
    const double e = v.normal.dot(p - v.point);
    out.planar.H.noalias() += c.weight * J * J.transpose();
    out.planar.b.noalias() += c.weight * J * e;
    out.planar.squared_residuals += c.squared_residual;
    ++out.planar.count;
  } else {
    // e = p - q;  de/d(rho, phi) = [I, -[p]x]
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>().setIdentity();
    J.rightCols<3>() = -skew(p);
    const Eigen::Vector3d e = p - v.point;
    out.point.H.noalias() += c.weight * J.transpose() * J;
    out.point.b.noalias() += c.weight * J.transpose() * e;
    out.point.squared_residuals += c.squared_residual;
    ++out.point.count;
  }
}

}  // namespace

Correspondence evaluateCorrespondence(const Eigen::Vector3d& point, std::uint8_t label,
                                      const MapVoxel& voxel, double sigma,
                                      const RegistrationParams& params) {
  Correspondence c;
  c.planar = params.point_to_plane && isPlanar(voxel, params.planarity_threshold);
  const Eigen::Vector3d d = point - voxel.point;
  const double e = c.planar ? voxel.normal.dot(d) : 0.0;
  c.squared_residual = c.planar ? e * e : d.squaredNorm();
  const bool known_geometry = voxel.planarity >= 0.f;
  if (!known_geometry && !params.sparse_voxel_pairs) return c;  // weight 0
  c.weight = gemanMcClureWeight(c.squared_residual, sigma / 3.0) *
             occupancyWeight(voxel.occupancy, params.gamma) *
             semanticWeight(label, voxel.label, voxel.label_prob, params.w_lower);
  return c;
}

RegistrationResult registerScan(const LabeledCloud& scan, const LocalMap& map,
                                const Eigen::Isometry3d& initial_guess, double sigma,
                                const RegistrationParams& params) {
  RegistrationResult result;
  result.pose = initial_guess;
  if (scan.size() == 0 || map.empty()) return result;
  const double max_distance = 3.0 * sigma;
  // Re-association can make the iteration cycle through a few correspondence sets with steps
  // above the tolerance: returning to a pose of the last kCycle iterations also ends it.
  constexpr std::size_t kCycle = 6;
  std::deque<Eigen::Isometry3d> recent;

  for (int it = 0; it < params.max_iterations; ++it) {
    const Eigen::Isometry3d pose = result.pose;
    const Systems sys = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, scan.size(), 256), Systems{},
        [&](const tbb::blocked_range<std::size_t>& range, Systems local) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Eigen::Vector3d p = pose * scan.points[i].cast<double>();
            const auto nn = map.nearest(p, max_distance);
            if (!nn) continue;
            const MapVoxel& v = map.voxel(nn->index);
            const std::uint8_t label = scan.hasLabels() ? scan.labels[i] : 0;
            accumulate(p, v, evaluateCorrespondence(p, label, v, sigma, params), local);
          }
          return local;
        },
        [](Systems a, const Systems& b) { return a += b; });

    result.iterations = it + 1;
    result.planar = sys.planar.count;
    result.non_planar = sys.point.count;
    const int total = sys.planar.count + sys.point.count;
    if (total < 6) break;  // under-determined: keep the current estimate
    result.alpha = static_cast<double>(sys.planar.count) / total;
    result.rms_residual =
        std::sqrt((sys.planar.squared_residuals + sys.point.squared_residuals) / total);
    const Matrix6d H = result.alpha * sys.planar.H + (1.0 - result.alpha) * sys.point.H;
    result.information = H;
    result.planar_information = sys.planar.H;
    const Vector6d b = result.alpha * sys.planar.b + (1.0 - result.alpha) * sys.point.b;
    const Vector6d dx = H.ldlt().solve(-b);
    if (!dx.allFinite()) break;
    result.pose = applyIncrement(dx, result.pose);
    if (dx.norm() < params.convergence) {
      result.converged = true;
      break;
    }
    for (const Eigen::Isometry3d& old : recent)
      if (logSe3(old.inverse() * result.pose).norm() < params.convergence) result.stalled = true;
    if (result.stalled) break;
    recent.push_back(result.pose);
    if (recent.size() > kCycle) recent.pop_front();
  }
  return result;
}

}  // namespace socc::odom
