#include "socc/odom/registration.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <type_traits>

#include "socc/odom/se3.hpp"
#include "socc/odom/weights.hpp"

namespace socc::odom {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Normal equations of one residual type (left-perturbation Jacobians J in the map frame). For the
// continuous-time part the moments in the point's time s are kept too: the Jacobian of the twist
// correction is s * M * J with one matrix M per iteration (see twistJacobianMap), so three 6x6
// sums give the whole 12x12 system.
struct System {
  Matrix6d H = Matrix6d::Zero();   // sum w J J^T
  Matrix6d H1 = Matrix6d::Zero();  // sum w s J J^T
  Matrix6d H2 = Matrix6d::Zero();  // sum w s^2 J J^T
  Vector6d b = Vector6d::Zero();   // sum w J e
  Vector6d b1 = Vector6d::Zero();  // sum w s J e
  int count = 0;
  double squared_residuals = 0.0;  // unweighted, for the health check
  double weighted_squares = 0.0;   // sum w e^2: the residuals' scale for the twist prior
  double weights = 0.0;
  System& operator+=(const System& o) {
    H += o.H;
    H1 += o.H1;
    H2 += o.H2;
    b += o.b;
    b1 += o.b1;
    count += o.count;
    squared_residuals += o.squared_residuals;
    weighted_squares += o.weighted_squares;
    weights += o.weights;
    return *this;
  }
  // jt: the residual's Jacobian transposed (6 x rows), e: the residual.
  template <int Rows>
  void add(const Eigen::Matrix<double, 6, Rows>& jt, const Eigen::Matrix<double, Rows, 1>& e,
           double w, double squared_residual, const double* time) {
    const Matrix6d jjt = w * jt * jt.transpose();
    const Vector6d je = w * jt * e;
    H += jjt;
    b += je;
    if (time) {
      H1 += *time * jjt;
      H2 += *time * *time * jjt;
      b1 += *time * je;
    }
    squared_residuals += squared_residual;
    weighted_squares += w * squared_residual;
    weights += w;
    ++count;
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
                const double* time, Systems& out) {
  if (c.planar) {
    // e = n . (p - q);  de/d(rho, phi) = [n^T, (p x n)^T]
    Vector6d jt;
    jt.head<3>() = c.normal;
    jt.tail<3>() = p.cross(c.normal);
    const Eigen::Matrix<double, 1, 1> e(c.normal.dot(p - v.point));
    out.planar.add<1>(jt, e, c.weight, c.squared_residual, time);
  } else {
    // e = p - q;  de/d(rho, phi) = [I, -[p]x]
    Eigen::Matrix<double, 6, 3> jt;
    jt.topRows<3>().setIdentity();
    jt.bottomRows<3>() = skew(p);
    out.point.add<3>(jt, p - v.point, c.weight, c.squared_residual, time);
  }
}

// M with (Jacobian of the body-twist correction) = s * M * J: J taken about the sensor's position
// t instead of the map origin ([I 0; -[t]x I]), then rotated into the body frame (R^T).
Matrix6d twistJacobianMap(const Eigen::Isometry3d& pose) {
  Matrix6d about_sensor = Matrix6d::Identity();
  about_sensor.bottomLeftCorner<3, 3>() = -skew(pose.translation());
  Matrix6d to_body = Matrix6d::Zero();
  to_body.topLeftCorner<3, 3>() = pose.linear().transpose();
  to_body.bottomRightCorner<3, 3>() = pose.linear().transpose();
  return to_body * about_sensor;
}

// The body twist c as a map-frame velocity field: a point p at time s moves by
// s * (v + w x p), (v, w) returned translation first.
Vector6d mapFrameTwist(const Eigen::Isometry3d& pose, const Vector6d& c) {
  Vector6d out;
  out.tail<3>() = pose.linear() * c.tail<3>();
  out.head<3>() = pose.linear() * c.head<3>() + pose.translation().cross(out.tail<3>());
  return out;
}

// The nearest map voxel of each scan point within the bound, kept across iterations. A point
// that moved by less than half the gap between its nearest and second-nearest voxel since it was
// searched still has the same nearest voxel (triangle inequality), so late iterations, whose
// steps are millimetres, search almost nothing. A point that moved further is searched within
// its old second-nearest distance plus the move (two voxels lie within it), not within the whole
// bound. The answers are those of a fresh search.
class NearestCache {
 public:
  NearestCache(const LocalMap& map, std::size_t points, double max_distance)
      : map_(map), max_distance_(max_distance), entries_(points) {}
  // Called for each i by one thread at a time.
  std::optional<std::size_t> nearest(std::size_t i, const Eigen::Vector3d& p) {
    Entry& e = entries_[i];
    double bound = max_distance_;
    if (e.searched && e.nearest) {
      const double moved = (p - e.at).norm();
      if (moved < (e.second - e.first) / 2) {
        const bool within = (p - map_.voxel(*e.nearest).point).norm() < max_distance_;
        return within ? e.nearest : std::nullopt;
      }
      bound = std::min(bound, e.second + moved + 1e-9);
    }
    const NearestTwo n = map_.nearestTwo(p, bound);
    e.searched = true;
    e.at = p;
    e.nearest.reset();  // none within the bound: searched again next time
    if (n.nearest) {
      e.nearest = n.nearest->index;
      e.first = std::sqrt(n.nearest->squared_distance);
      e.second = std::sqrt(n.second_squared_distance);  // or the bound: no nearer
    }
    return e.nearest;
  }

 private:
  struct Entry {
    Eigen::Vector3d at = Eigen::Vector3d::Zero();  // where it was searched
    std::optional<std::size_t> nearest;
    double first = 0.0;   // its distance from `at`
    double second = 0.0;  // the second nearest's (at least)
    bool searched = false;
  };
  const LocalMap& map_;
  double max_distance_;
  std::vector<Entry> entries_;
};

// One Gauss-Newton step of pose and (with a prior) the twist correction c.
struct Step {
  Vector6d pose = Vector6d::Zero();
  Vector6d twist = Vector6d::Zero();
};

// Holds the sensor's position along params.hold_direction: a linear constraint on the step worth
// hold_pairs planar pairs (H, b as in H x = -b). A left increment (rho, phi) moves the position t
// by rho + phi x t.
void addHold(const RegistrationParams& params, const Eigen::Isometry3d& pose, double alpha,
             Matrix6d& H, Vector6d& b) {
  const Eigen::Vector3d& u = params.hold_direction;
  if (u.squaredNorm() < 0.5 || params.hold_pairs <= 0.0) return;
  Vector6d a;
  a.head<3>() = u;
  a.tail<3>() = pose.translation().cross(u);
  const double offset = u.dot(pose.translation() - params.hold_position);
  // The planar pairs enter the mixed system scaled by alpha.
  const double stiffness = alpha * params.hold_pairs;
  H += stiffness * a * a.transpose();
  b += stiffness * offset * a;
}

// Holds the tilt towards params.tilt: residual r = R g - u (g the sensor's up, u the map's),
// J = -[R g]x for a left increment. Its information is the data's own on the rotation (with the
// translation marginalised: the same about any point), seen through J, times gain / (1 - gain):
// the two together put each tilt axis gain of the way from the scan's answer to the reference's.
void addTilt(const RegistrationParams& params, const Eigen::Isometry3d& pose, Matrix6d& H,
             Vector6d& b) {
  if (!params.tilt || params.tilt->gain <= 0.0) return;
  const Eigen::Vector3d v = pose.linear() * params.tilt->sensor_up;
  const Eigen::Matrix3d rotation_info =
      H.bottomRightCorner<3, 3>() -
      H.bottomLeftCorner<3, 3>() * H.topLeftCorner<3, 3>().ldlt().solve(H.topRightCorner<3, 3>());
  const double gain = std::min(params.tilt->gain, 0.99);
  const Eigen::Matrix3d jt = skew(v);  // J^T = (-[v]x)^T
  const Eigen::Matrix3d info = gain / (1.0 - gain) * jt * rotation_info * jt.transpose();
  if (!info.allFinite()) return;
  H.bottomRightCorner<3, 3>() += jt * info * jt.transpose();
  b.tail<3>() += jt * info * (v - params.tilt->map_up);
}

Step solve(const Systems& sys, double alpha, const Eigen::Isometry3d& pose, const Vector6d& c,
           const SweepTwistPrior* prior, const RegistrationParams& params) {
  const auto mix = [alpha](const auto& planar, const auto& point) {
    using T = std::decay_t<decltype(planar)>;
    return T(alpha * planar + (1.0 - alpha) * point);
  };
  Matrix6d H = mix(sys.planar.H, sys.point.H);
  Vector6d b = mix(sys.planar.b, sys.point.b);
  addHold(params, pose, alpha, H, b);
  addTilt(params, pose, H, b);
  Step step;
  if (!prior) {
    step.pose = H.ldlt().solve(-b);
    return step;
  }
  const Matrix6d M = twistJacobianMap(pose);
  // The data term is sum w e^2 in m^2: the prior's information is scaled by the residuals'
  // (robustly weighted) variance so that both are in the same units.
  const double weights = mix(sys.planar.weights, sys.point.weights);
  const double variance =
      weights > 0.0 ? mix(sys.planar.weighted_squares, sys.point.weighted_squares) / weights : 0.0;
  const Vector6d info = std::max(variance, 2.5e-5) *
                        prior->sigma.cwiseAbs2().cwiseMax(1e-12).cwiseInverse();  // 0: held
  Eigen::Matrix<double, 12, 12> A;
  A.topLeftCorner<6, 6>() = H;
  A.topRightCorner<6, 6>() = mix(sys.planar.H1, sys.point.H1) * M.transpose();
  A.bottomLeftCorner<6, 6>() = A.topRightCorner<6, 6>().transpose();
  A.bottomRightCorner<6, 6>() = M * mix(sys.planar.H2, sys.point.H2) * M.transpose();
  A.bottomRightCorner<6, 6>().diagonal() += info;
  Eigen::Matrix<double, 12, 1> g;
  g.head<6>() = b;
  g.tail<6>() = M * mix(sys.planar.b1, sys.point.b1) + info.cwiseProduct(c + prior->offset);
  const Eigen::Matrix<double, 12, 1> x = A.ldlt().solve(-g);
  step.pose = x.head<6>();
  step.twist = x.tail<6>();
  return step;
}

// pose within distance (twist norm) of one of path's poses.
bool joins(const Eigen::Isometry3d& pose, const std::vector<Eigen::Isometry3d>& path,
           double distance) {
  for (const Eigen::Isometry3d& p : path)
    if ((p.translation() - pose.translation()).norm() < distance &&
        logSe3(p.inverse() * pose).norm() < distance)
      return true;
  return false;
}

// evaluateCorrespondence with the voxel's w_occ given (OccupancyWeights in registerScan).
Correspondence weighCorrespondence(const Eigen::Vector3d& point, std::uint8_t label,
                                   const MapVoxel& voxel, double sigma,
                                   const RegistrationParams& params,
                                   const Eigen::Vector3d& scan_normal, double occupancy_weight) {
  Correspondence c;
  const bool known_geometry = voxel.planarity >= 0.f;
  c.planar = params.point_to_plane && isPlanar(voxel, params.planarity_threshold);
  c.normal = voxel.normal;
  if (params.point_to_plane && !known_geometry && scan_normal.squaredNorm() > 0.5) {
    c.planar = true;  // along the scan's surface: no pull along it (scan_normals.hpp)
    c.normal = scan_normal;
  }
  const Eigen::Vector3d d = point - voxel.point;
  const double e = c.planar ? c.normal.dot(d) : 0.0;
  c.squared_residual = c.planar ? e * e : d.squaredNorm();
  if (!known_geometry && !params.sparse_voxel_pairs) return c;               // weight 0
  if (!known_geometry && !c.planar && !params.sparse_point_pairs) return c;  // weight 0
  c.weight = gemanMcClureWeight(c.squared_residual, sigma / 3.0) * occupancy_weight *
             semanticWeight(label, voxel.label, voxel.label_prob, params.w_lower);
  return c;
}

}  // namespace

Correspondence evaluateCorrespondence(const Eigen::Vector3d& point, std::uint8_t label,
                                      const MapVoxel& voxel, double sigma,
                                      const RegistrationParams& params,
                                      const Eigen::Vector3d& scan_normal) {
  return weighCorrespondence(point, label, voxel, sigma, params, scan_normal,
                             occupancyWeight(voxel.occupancy, params.gamma));
}

RegistrationResult registerScan(const LabeledCloud& scan, const LocalMap& map,
                                const Eigen::Isometry3d& initial_guess, double sigma,
                                const RegistrationParams& params,
                                const SweepTwistPrior* twist_prior,
                                const ScanNormals* scan_normals) {
  RegistrationResult result;
  result.pose = initial_guess;
  if (scan.size() == 0 || map.empty()) return result;
  if (!scan.hasTimes()) twist_prior = nullptr;
  const bool with_normals = scan_normals != nullptr && scan_normals->size() == scan.size();
  // The change of the twist correction that moves the sweep's ends by one convergence step.
  double half_span = 0.0;
  if (twist_prior)
    for (const float t : scan.times) half_span = std::max(half_span, std::abs(double{t}));
  const double max_distance = 3.0 * sigma;
  // Re-association can make the iteration cycle through a few correspondence sets with steps
  // above the tolerance: returning to a pose of the last kCycle iterations also ends it.
  constexpr std::size_t kCycle = 6;
  std::deque<Eigen::Isometry3d> recent;
  NearestCache nearest(map, scan.size(), max_distance);
  const OccupancyWeights occupancy_weight(params.gamma);

  for (int it = 0; it < params.max_iterations; ++it) {
    const Eigen::Isometry3d pose = result.pose;
    const Vector6d motion = mapFrameTwist(pose, result.twist_correction);
    const Systems sys = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, scan.size(), 256), Systems{},
        [&](const tbb::blocked_range<std::size_t>& range, Systems local) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            Eigen::Vector3d p = pose * scan.points[i].cast<double>();
            const double s = twist_prior ? double{scan.times[i]} : 0.0;
            if (twist_prior) p += s * (motion.head<3>() + motion.tail<3>().cross(p));
            const std::optional<std::size_t> nn = nearest.nearest(i, p);
            if (!nn) continue;
            const MapVoxel& v = map.voxel(*nn);
            const std::uint8_t label = scan.hasLabels() ? scan.labels[i] : 0;
            // evaluateCorrespondence takes the scan's normal only where the voxel has none.
            const Eigen::Vector3d normal =
                with_normals && v.planarity < 0.f
                    ? Eigen::Vector3d(pose.linear() * scan_normals->at(i).cast<double>())
                    : Eigen::Vector3d::Zero();
            accumulate(p, v,
                       weighCorrespondence(p, label, v, sigma, params, normal,
                                           occupancy_weight(v.occupancy)),
                       twist_prior ? &s : nullptr, local);
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
    result.information = result.alpha * sys.planar.H + (1.0 - result.alpha) * sys.point.H;
    result.planar_information = sys.planar.H;
    const Step step = solve(sys, result.alpha, pose, result.twist_correction, twist_prior, params);
    if (!step.pose.allFinite() || !step.twist.allFinite()) break;
    result.pose = applyIncrement(step.pose, result.pose);
    result.twist_correction += step.twist;
    if (step.pose.norm() + step.twist.norm() * half_span < params.convergence) {
      result.converged = true;
      break;
    }
    for (const Eigen::Isometry3d& old : recent)
      if (logSe3(old.inverse() * result.pose).norm() < params.convergence) result.stalled = true;
    if (params.join_distance > 0.0) {
      result.path.push_back(result.pose);
      result.joined = joins(result.pose, params.join_path, params.join_distance);
    }
    if (result.stalled || result.joined) break;
    recent.push_back(result.pose);
    if (recent.size() > kCycle) recent.pop_front();
  }
  return result;
}

}  // namespace socc::odom
