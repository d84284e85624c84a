#include "socc/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace socc::sim {

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                              double alpha) {
  const Eigen::Isometry3d rel = a.inverse() * b;
  Eigen::AngleAxisd aa(rel.linear());
  aa.angle() *= alpha;
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = aa.toRotationMatrix();
  step.translation() = alpha * rel.translation();
  return a * step;
}

Trajectory::Trajectory(Poses keyframes, double period)
    : keyframes_(std::move(keyframes)), period_(period) {
  if (keyframes_.size() < 2) throw std::invalid_argument("a trajectory needs 2 keyframes");
  if (!(period > 0.0)) throw std::invalid_argument("keyframe period must be > 0");
}

Eigen::Isometry3d Trajectory::poseAt(double t) const {
  const Eigen::Isometry3d route = routePoseAt(t);
  if (!body_) return route;
  // The route's acceleration and speed (sensor frame) from central differences over 0.3 s, long
  // enough to smooth the centimetre noise of recorded (GPS/INS) trajectories.
  constexpr double kH = 0.3;
  const Eigen::Vector3d before = routePoseAt(t - kH).translation();
  const Eigen::Vector3d after = routePoseAt(t + kH).translation();
  const Eigen::Vector3d accel = (after - 2.0 * route.translation() + before) / (kH * kH);
  const double speed = (after - before).norm() / (2.0 * kH);
  return route * body_->offset(t, route.linear().transpose() * accel, speed);
}

Eigen::Isometry3d Trajectory::routePoseAt(double t) const {
  // Before the first keyframe the route goes on as its first segment does, as after the last:
  // held at its start, a route under way would "accelerate" from rest at t = 0, and the body
  // model would pitch the sensor by degrees over the first frames.
  double u = t / period_;
  if (std::abs(u - std::round(u)) < 1e-9) u = std::round(u);  // frame times hit keyframes exactly
  const std::size_t last = keyframes_.size() - 1;
  const std::size_t k = u <= 0.0 ? 0 : std::min(static_cast<std::size_t>(std::floor(u)), last - 1);
  const double alpha = u - static_cast<double>(k);
  if (alpha == 0.0) return keyframes_[k];  // exact keyframes (frame poses) stay exact
  return interpolate(keyframes_[k], keyframes_[k + 1], alpha);
}

Trajectory followPath(const Path& path, double speed, double s0, double duration) {
  constexpr double kPeriod = 0.01;
  const auto n = static_cast<std::size_t>(std::ceil(duration / kPeriod)) + 1;
  Poses keyframes;
  for (std::size_t i = 0; i <= std::max<std::size_t>(n, 1); ++i) {
    const PathPoint p = path.at(s0 + speed * kPeriod * static_cast<double>(i));
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(p.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = p.position;
    keyframes.push_back(pose);
  }
  return Trajectory(std::move(keyframes), kPeriod);
}

}  // namespace socc::sim
