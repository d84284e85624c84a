#pragma once
// Finding where a new keyframe was seen before (a revisit of one robot, an encounter of two)
// and proving it: candidates come from the estimated positions (within the odometry's drift)
// and from the place descriptor (Scan Context), and each is verified as a relocalization
// against the candidate's submap (submap_access.hpp). Only a verified candidate becomes a
// loop edge.
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "consistency_params.hpp"
#include "keyframe.hpp"
#include "socc/map/map_config.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/relocalization.hpp"

namespace socc::consistency {

struct Closure {
  int from = 0;                                                // candidate (older) keyframe
  int to = 0;                                                  // the new keyframe
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  // from_T_to
  double fitness = 0.0;
  double free = 0.0;
  bool by_descriptor = false;  // found by Scan Context (else by position)
};

/// Candidates refused by verification, counted by why (odom::Refusal as index).
using RefusalCounts = std::array<int, odom::kRefusalKinds>;

struct RecognitionTally {
  int attempts = 0;      // keyframes with candidates
  int verified = 0;      // closures accepted
  int refused = 0;       // attempts whose candidates all failed verification
  int inconsistent = 0;  // verified closures the pose graph refused (addConsistentEdge)
  double seconds = 0.0;  // spent verifying
  RefusalCounts candidates_refused{};  // the candidates of all attempts, by why
};

/// Candidate keyframes for keyframes[query] with a guess of the query's pose in each candidate's
/// frame. estimate(i): keyframe i's current pose in the map frame.
struct Candidate {
  int keyframe = 0;
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  bool by_descriptor = false;
};
std::vector<Candidate> findCandidates(const std::vector<Keyframe>& keyframes, int query,
                                      const std::vector<Eigen::Isometry3d>& estimates,
                                      const ConsistencyParams& params);

/// Verifies the query against candidate's submap; the closure when it passes every check.
/// problem: why the last candidate tried was refused; refused: each refused candidate counted
/// by why (added to).
std::optional<Closure> verifyCandidate(
    const std::vector<Keyframe>& keyframes, int query, const std::vector<Candidate>& candidates,
    const std::vector<Eigen::Isometry3d>& estimates, const ConsistencyParams& params,
    const map::MapConfig& map_config, const odom::OdomConfig& odom_config,
    std::string* problem = nullptr, RefusalCounts* refused = nullptr);

}  // namespace socc::consistency
