#pragma once
// The relocalization's view of a map (odom::MapAccess) over a few keyframes instead of the
// shared grid: the keyframes are integrated, rays and all, into a small private grid in the
// frame of the candidate keyframe. A loop closure is then verified exactly as a robot
// relocalizes (odom::relocalize): SOCC-ICP from each guess against that grid's chunk, the
// odometry's health check, the share of the scan explained, the server's free-space check and
// the margin over any other place that also fits.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/odom/relocalization.hpp"

namespace socc::consistency {

/// One keyframe scan of the submap: points in its sensor frame, pose in the submap frame.
struct SubmapScan {
  const std::vector<Eigen::Vector3f>* points = nullptr;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

class SubmapAccess : public odom::MapAccess {
 public:
  /// guesses: the candidate poses of the query scan in the submap frame (candidates() returns
  /// them as the server's search would).
  SubmapAccess(const map::MapConfig& config, const std::vector<SubmapScan>& scans,
               std::vector<Eigen::Isometry3d> guesses, double chunk_radius);

  std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                            const std::optional<odom::PoseHint>& hint,
                                            int max) override;
  odom::LocalMap chunk(const Eigen::Vector3d& center) override;
  std::vector<odom::SpaceCheck> check(const std::vector<Eigen::Vector3f>& scan,
                                      const std::vector<Eigen::Isometry3d>& poses) override;

  const map::SemanticOccupancyMap& grid() const { return map_; }

 private:
  map::SemanticOccupancyMap map_;
  std::vector<Eigen::Isometry3d> guesses_;
  double chunk_radius_;
};

}  // namespace socc::consistency
