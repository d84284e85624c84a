#pragma once
// A keyframe's gravity reference from every integration it stands for (docs/consistency.md
// "Gravity reference"). Keyframes are metres apart, integrations ten a second, and each
// integration carries its own reading of the up direction, whose error is in part white (it
// changes from one reading to the next). The map's tilt rests on the first keyframe's reference
// (the map frame is held at it), so one reading's white error there tilts the whole map. The
// window takes the mean of the up directions of the integrations from a keyframe to the robot's
// next one, each turned into the keyframe's sensor frame by the integrated relative rotation
// (a few metres of odometry: far below a reading's error). Its sigma stays the largest stated
// one: the slowly varying bias and the mounting misalignment do not average out. A reading more
// than kMaxSigmas from the window's mean so far is left out (a pose that jumped).
#include <Eigen/Geometry>
#include <optional>

#include "gravity_reference.hpp"

namespace socc::consistency {

class GravityWindow {
 public:
  /// A new keyframe at keyframe_pose (the robot's integrated pose) with its own reading.
  void start(const Eigen::Isometry3d& keyframe_pose, const std::optional<GravityReference>& own);
  /// A later integration of the same robot at pose (before the window started: ignored).
  void add(const Eigen::Isometry3d& pose, const std::optional<GravityReference>& reading);
  /// The keyframe's reference from its window: none until an integration after the keyframe
  /// carried a reading (the keyframe's own reading is then its reference as it is).
  std::optional<GravityReference> reference() const;

 private:
  void take(const Eigen::Vector3d& up_in_keyframe, double sigma);

  static constexpr double kMaxSigmas = 5.0;  // a reading this far from the mean is an outlier

  std::optional<Eigen::Matrix3d> keyframe_rotation_;  // map_R_keyframe
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();     // in the keyframe's sensor frame
  double sigma_ = 0.0;                                // the largest stated
  int after_ = 0;                                     // readings after the keyframe's own
};

}  // namespace socc::consistency
