#include "pose_graph.hpp"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace socc::consistency {
namespace {

Matrix6d sqrtInformation(const Matrix6d& information) {
  // Upper factor U with U^T U = information, so that |U r|^2 is the Mahalanobis error.
  return information.llt().matrixU();
}

// Residual of a relative pose: the measured from_T_to against the estimate, translation and
// twice the vector part of the rotation error, weighed by the square root of the information.
struct RelativePoseError {
  RelativePoseError(const Eigen::Isometry3d& measured, const Matrix6d& sqrt_information)
      : t_measured(measured.translation()),
        q_measured(measured.linear()),
        sqrt_information(sqrt_information) {}

  template <typename T>
  bool operator()(const T* t_a, const T* q_a, const T* t_b, const T* q_b, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(t_a), tb(t_b);
    const Eigen::Map<const Eigen::Quaternion<T>> qa(q_a), qb(q_b);
    const Eigen::Quaternion<T> qa_inv = qa.conjugate();
    const Eigen::Matrix<T, 3, 1> t_ab = qa_inv * (tb - ta);
    const Eigen::Quaternion<T> q_ab = qa_inv * qb;
    const Eigen::Quaternion<T> dq = q_measured.template cast<T>().conjugate() * q_ab;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = t_ab - t_measured.template cast<T>();
    r.template tail<3>() = T(2.0) * dq.vec();
    r.applyOnTheLeft(sqrt_information.template cast<T>());
    return true;
  }

  Eigen::Vector3d t_measured;
  Eigen::Quaterniond q_measured;
  Matrix6d sqrt_information;
};

struct AbsolutePoseError {
  AbsolutePoseError(const Eigen::Isometry3d& prior, const Matrix6d& sqrt_information)
      : t_prior(prior.translation()), q_prior(prior.linear()), sqrt_information(sqrt_information) {}

  template <typename T>
  bool operator()(const T* t_p, const T* q_p, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(t_p);
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_p);
    const Eigen::Quaternion<T> dq = q_prior.template cast<T>().conjugate() * q;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = t - t_prior.template cast<T>();
    r.template tail<3>() = T(2.0) * dq.vec();
    r.applyOnTheLeft(sqrt_information.template cast<T>());
    return true;
  }

  Eigen::Vector3d t_prior;
  Eigen::Quaterniond q_prior;
  Matrix6d sqrt_information;
};

// Residual of a gravity prior: the graph's up direction u seen from the node (R^T u) against
// the measured up, over sigma. Three components of a 2-dof error (both are unit vectors).
struct GravityError {
  GravityError(const Eigen::Vector3d& up, double sigma) : up_measured(up), weight(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* q_p, const T* u_p, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_p);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> u(u_p);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = (q.conjugate() * u - up_measured.template cast<T>()) * T(weight);
    return true;
  }

  Eigen::Vector3d up_measured;
  double weight;
};

}  // namespace

Matrix6d isotropicInformation(double sigma_t, double sigma_r) {
  Matrix6d information = Matrix6d::Zero();
  information.diagonal() << Eigen::Vector3d::Constant(1.0 / (sigma_t * sigma_t)),
      Eigen::Vector3d::Constant(1.0 / (sigma_r * sigma_r));
  return information;
}

int PoseGraph::addNode(const Eigen::Isometry3d& pose) {
  poses_.push_back(pose);
  return static_cast<int>(poses_.size()) - 1;
}

double PoseGraph::edgeError(const PoseEdge& edge) const {
  const RelativePoseError error(edge.relative, sqrtInformation(edge.information));
  const Eigen::Isometry3d& a = pose(edge.from);
  const Eigen::Isometry3d& b = pose(edge.to);
  const Eigen::Vector3d ta = a.translation(), tb = b.translation();
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Eigen::Matrix<double, 6, 1> r;
  error(ta.data(), qa.coeffs().data(), tb.data(), qb.coeffs().data(), r.data());
  return r.squaredNorm();
}

double PoseGraph::priorError(const PosePrior& prior) const {
  const AbsolutePoseError error(prior.pose, sqrtInformation(prior.information));
  const Eigen::Vector3d t = pose(prior.node).translation();
  const Eigen::Quaterniond q(pose(prior.node).linear());
  Eigen::Matrix<double, 6, 1> r;
  error(t.data(), q.coeffs().data(), r.data());
  return r.squaredNorm();
}

void PoseGraph::addGravityPrior(const GravityPrior& prior) {
  if (prior.node < 0 || prior.node >= static_cast<int>(poses_.size()))
    throw std::logic_error("pose graph: no node " + std::to_string(prior.node));
  const double norm = prior.up.norm();
  if (!(prior.sigma > 0.0) || !std::isfinite(prior.sigma) || !(norm > 0.0) || !std::isfinite(norm))
    throw std::invalid_argument("pose graph: a gravity prior needs sigma > 0 and an up vector");
  GravityPrior p = prior;
  p.up /= norm;
  if (!up_) up_ = (pose(p.node).linear() * p.up).normalized();
  gravity_.push_back(p);
}

double PoseGraph::gravityError(const GravityPrior& prior) const {
  if (!up_) return 0.0;
  const GravityError error(prior.up, prior.sigma);
  const Eigen::Quaterniond q(pose(prior.node).linear());
  Eigen::Vector3d r;
  error(q.coeffs().data(), up_->data(), r.data());
  return r.squaredNorm();
}

double PoseGraph::chi2() const {
  double sum = 0.0;
  for (const PoseEdge& e : edges_) sum += edgeError(e);
  for (const PosePrior& p : priors_)
    if (!p.fixed) sum += priorError(p);
  for (const GravityPrior& g : gravity_) sum += gravityError(g);
  return sum;
}

double PoseGraph::optimumCost() {
  const double current = chi2();
  if (current <= 0.0) return current;
  const std::size_t nodes = poses_.size(), edges = edges_.size(), priors = priors_.size(),
                    gravity = gravity_.size();
  if (optimum_ && optimum_->nodes == nodes && optimum_->edges == edges &&
      optimum_->priors == priors && optimum_->gravity == gravity)
    return std::min(current, optimum_->chi2);  // unchanged since: the same optimization
  // The current poses were the optimum and all that was added since holds exactly at them
  // (a new keyframe continued by its integrated odometry): they still are (its gradient is 0).
  // A new gravity prior rarely holds exactly (its sensor's tilt is measured, not chained), so
  // with gravity references the graph without the closure is optimized again at each attempt.
  constexpr double kHolds = 1e-12;  // squared Mahalanobis error: rounding only
  const bool still_optimal =
      optimum_ && optimum_->at_poses && optimum_->edges <= edges && optimum_->priors <= priors &&
      optimum_->gravity <= gravity &&
      std::all_of(edges_.begin() + static_cast<std::ptrdiff_t>(optimum_->edges), edges_.end(),
                  [&](const PoseEdge& e) { return edgeError(e) <= kHolds; }) &&
      std::all_of(priors_.begin() + static_cast<std::ptrdiff_t>(optimum_->priors), priors_.end(),
                  [&](const PosePrior& p) { return priorError(p) <= kHolds; }) &&
      std::all_of(gravity_.begin() + static_cast<std::ptrdiff_t>(optimum_->gravity), gravity_.end(),
                  [&](const GravityPrior& g) { return gravityError(g) <= kHolds; });
  if (still_optimal) {
    optimum_ = Optimum{nodes, edges, priors, gravity, current, true};
    return current;
  }
  PoseGraph without = *this;
  without.optimize();
  optimum_ = Optimum{nodes, edges, priors, gravity, without.chi2(), false};
  return std::min(current, optimum_->chi2);
}

bool PoseGraph::addConsistentEdge(const PoseEdge& edge, double max_chi2, double* chi2_increase,
                                  OptimizationSummary* summary) {
  // Without it, optimized: the current poses need not be the optimum (a new odometry edge that
  // measures a snap the integrated poses contain), and that residual is no closure's merit.
  const double before = optimumCost();
  PoseGraph trial = *this;
  trial.addEdge(edge);
  const OptimizationSummary s = trial.optimize();
  const double increase = trial.chi2() - before;
  if (chi2_increase) *chi2_increase = increase;
  if (summary) *summary = s;
  if (!(increase <= max_chi2)) return false;
  *this = std::move(trial);
  return true;
}

OptimizationSummary PoseGraph::optimize(int max_iterations) {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(poses_.size());
  const auto check = [n](int node) {
    if (node < 0 || node >= n)
      throw std::logic_error("pose graph: no node " + std::to_string(node));
  };
  std::vector<Eigen::Vector3d> t(poses_.size());
  std::vector<Eigen::Quaterniond> q(poses_.size());
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    t[i] = poses_[i].translation();
    q[i] = Eigen::Quaterniond(poses_[i].linear()).normalized();
  }
  ceres::Problem problem;
  ceres::Manifold* quaternion = new ceres::EigenQuaternionManifold;  // owned by the problem
  const auto addBlocks = [&](int node) {
    problem.AddParameterBlock(t[node].data(), 3);
    problem.AddParameterBlock(q[node].coeffs().data(), 4, quaternion);
  };
  for (int i = 0; i < n; ++i) addBlocks(i);
  for (const PoseEdge& e : edges_) {
    check(e.from);
    check(e.to);
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(e.relative, sqrtInformation(e.information)));
    problem.AddResidualBlock(cost, nullptr, t[e.from].data(), q[e.from].coeffs().data(),
                             t[e.to].data(), q[e.to].coeffs().data());
  }
  for (const PosePrior& p : priors_) {
    check(p.node);
    if (p.fixed) {
      t[p.node] = p.pose.translation();
      q[p.node] = Eigen::Quaterniond(p.pose.linear()).normalized();
      problem.SetParameterBlockConstant(t[p.node].data());
      problem.SetParameterBlockConstant(q[p.node].coeffs().data());
      continue;
    }
    auto* cost = new ceres::AutoDiffCostFunction<AbsolutePoseError, 6, 3, 4>(
        new AbsolutePoseError(p.pose, sqrtInformation(p.information)));
    problem.AddResidualBlock(cost, nullptr, t[p.node].data(), q[p.node].coeffs().data());
  }
  // The graph frame's up direction, on the unit sphere, estimated with the poses.
  Eigen::Vector3d up = up_.value_or(Eigen::Vector3d::UnitZ());
  if (!gravity_.empty()) problem.AddParameterBlock(up.data(), 3, new ceres::SphereManifold<3>);
  for (const GravityPrior& g : gravity_) {
    check(g.node);
    auto* cost =
        new ceres::AutoDiffCostFunction<GravityError, 3, 4, 3>(new GravityError(g.up, g.sigma));
    problem.AddResidualBlock(cost, nullptr, q[g.node].coeffs().data(), up.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q[i].normalized().toRotationMatrix();
    pose.translation() = t[i];
    poses_[i] = pose;
  }
  if (!gravity_.empty()) up_ = up.normalized();
  optimum_ = Optimum{poses_.size(), edges_.size(), priors_.size(), gravity_.size(), chi2(), true};
  OptimizationSummary out;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace socc::consistency
