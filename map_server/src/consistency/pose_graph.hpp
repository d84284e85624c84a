#pragma once
// The pose graph over the keyframes of all robots, optimized by Ceres (a maintained solver, not
// our own). Nodes are keyframe poses in the shared map frame. Odometry edges join a robot's
// consecutive keyframes with the relative pose of their integrations; loop (one robot) and
// encounter (two robots) edges come from verified registrations. A closure must also agree
// with the graph (addConsistentEdge): one whose optimized graph costs more than a chi-square
// bound over the graph without it contradicts the odometry and the other closures and is
// dropped, so a wrong edge that slipped through verification does not bend the map. Each
// robot's first keyframe has a prior at its integrated pose: the first robot's holds the map
// frame, the others' are weak (they joined at a relocalized pose, an estimate like any other).
// Gravity priors (a keyframe's up direction from its robot's IMU or INS) tie the nodes'
// attitudes to the graph frame's up direction, itself estimated with the poses: the one
// measurement of a tilt of the whole map (docs/consistency.md "Gravity reference").
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace socc::consistency {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct PoseEdge {
  int from = 0;
  int to = 0;
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  // from_T_to
  Matrix6d information = Matrix6d::Identity();  // translation first, rotation (rad) second
};

struct PosePrior {
  int node = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Matrix6d information = Matrix6d::Identity();
  bool fixed = false;  // the node is held at pose (the map frame's anchor)
};

// A node's measured up direction: residual (R^T u - up) / sigma, with R the node's rotation
// (map_T_sensor) and u the graph frame's up direction (PoseGraph::up, a unit vector estimated
// with the poses, not assumed +z: the map frame is the first keyframe's sensor frame, which
// need not be level). Its squared norm is 2 (1 - cos angle) / sigma^2, about angle^2 / sigma^2.
struct GravityPrior {
  int node = 0;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // in the node's (sensor) frame, unit
  double sigma = 0.01;                            // [rad] > 0
};

struct OptimizationSummary {
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
};

/// Information of a relative pose with standard deviations sigma_t [m] and sigma_r [rad].
Matrix6d isotropicInformation(double sigma_t, double sigma_r);

class PoseGraph {
 public:
  /// Adds a node; returns its index.
  int addNode(const Eigen::Isometry3d& pose);
  void addEdge(const PoseEdge& edge) { edges_.push_back(edge); }
  /// Replaces edge index (its nodes stay). Throws std::out_of_range on an index not in edges().
  void replaceEdge(std::size_t index, const PoseEdge& edge) {
    edges_.at(index) = edge;
    optimum_.reset();
  }
  void addPrior(const PosePrior& prior) { priors_.push_back(prior); }
  /// The first one sets the graph frame's up direction to its node's rotation times its up (so
  /// it holds exactly); later ones leave it to the optimization. Throws std::logic_error on a
  /// node that does not exist, std::invalid_argument on a sigma not > 0 or a zero up.
  void addGravityPrior(const GravityPrior& prior);

  /// Optimizes all nodes from their current poses. Throws std::logic_error on an edge or prior
  /// naming a node that does not exist.
  OptimizationSummary optimize(int max_iterations = 50);

  std::size_t size() const { return poses_.size(); }
  const Eigen::Isometry3d& pose(int node) const {
    return poses_.at(static_cast<std::size_t>(node));
  }
  void setPose(int node, const Eigen::Isometry3d& pose) {
    poses_.at(static_cast<std::size_t>(node)) = pose;
    optimum_.reset();
  }
  const std::vector<PoseEdge>& edges() const { return edges_; }
  const std::vector<PosePrior>& priors() const { return priors_; }
  const std::vector<GravityPrior>& gravityPriors() const { return gravity_; }
  /// The graph frame's up direction (unit): none before the first gravity prior.
  const std::optional<Eigen::Vector3d>& up() const { return up_; }

  /// Adds edge when the graph optimized with it costs at most max_chi2 (sum of squared
  /// Mahalanobis errors) more than the graph optimized without it; then the poses are the optimized
  /// ones. Otherwise the graph is left as it was and false is returned. chi2_increase: the increase
  /// measured.
  bool addConsistentEdge(const PoseEdge& edge, double max_chi2, double* chi2_increase = nullptr,
                         OptimizationSummary* summary = nullptr);

  /// Sum of squared Mahalanobis errors of all edges and priors at the current poses.
  double chi2() const;

  /// Squared Mahalanobis error of an edge at the current poses (for reporting outliers).
  double edgeError(const PoseEdge& edge) const;
  /// Squared Mahalanobis error of a prior at the current poses (a fixed one's too).
  double priorError(const PosePrior& prior) const;
  /// Squared error of a gravity prior at the current poses and up direction (0 without one).
  double gravityError(const GravityPrior& prior) const;

 private:
  /// The cost of this graph optimized from its current poses (addConsistentEdge's baseline):
  /// the last optimization's when nothing changed since, or nothing that moves the optimum.
  double optimumCost();

  // The last optimization's result (addConsistentEdge reuses it): the graph of the first
  // nodes/edges/priors elements optimized from the current poses costs chi2; at_poses: the
  // current poses are that optimum (this graph was optimized, not a copy).
  struct Optimum {
    std::size_t nodes = 0;
    std::size_t edges = 0;
    std::size_t priors = 0;
    std::size_t gravity = 0;
    double chi2 = 0.0;
    bool at_poses = false;
  };
  std::optional<Optimum> optimum_;

  std::vector<Eigen::Isometry3d> poses_;
  std::vector<PoseEdge> edges_;
  std::vector<PosePrior> priors_;
  std::vector<GravityPrior> gravity_;
  std::optional<Eigen::Vector3d> up_;  // estimated with the poses
};

}  // namespace socc::consistency
