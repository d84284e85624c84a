#pragma once
// The sensor's continuous-time pose: keyframes at a fixed rate, interpolated (and extrapolated
// past the last keyframe with the last motion) so that any instant of a sweep has a pose.
#include <Eigen/Geometry>
#include <optional>

#include "socc/kitti_io.hpp"
#include "socc/sim/body_motion.hpp"
#include "socc/sim/path.hpp"

namespace socc::sim {

class Trajectory {
 public:
  /// keyframes[k] is the pose at time k * period; at least 2 keyframes.
  Trajectory(Poses keyframes, double period);

  /// The route's pose at time t, moved by the body motion when there is one.
  Eigen::Isometry3d poseAt(double t) const;
  /// Adds the car body's own motion (realism "motion"); none: the smooth route only.
  void setBodyMotion(const BodyMotion& body) { body_ = body; }
  double duration() const { return period_ * static_cast<double>(keyframes_.size() - 1); }

 private:
  Eigen::Isometry3d routePoseAt(double t) const;

  Poses keyframes_;
  double period_;
  std::optional<BodyMotion> body_;
};

/// Drives along a path (whose points are sensor positions) at constant speed from arc length s0,
/// heading along the path, level; keyframes every 10 ms.
Trajectory followPath(const Path& path, double speed, double s0, double duration);

/// Interpolates between two poses (alpha in [0,1]; > 1 extrapolates).
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha);

}  // namespace socc::sim
