#pragma once
// How a robot's sensors are mounted relative to each other, as a bag records it: the static
// transforms of its /tf_static topic (tf2_msgs/TFMessage), e.g. from a LiDAR's frame to an IMU's.
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace socc::sensors {

class StaticTransforms {
 public:
  /// The transforms of the bag's /tf_static topic (none when it has none; malformed messages
  /// are skipped). A later transform of the same child frame replaces an earlier one.
  static StaticTransforms fromBag(const std::filesystem::path& bag);

  /// parent_T_child: the child frame's pose in the parent frame. Frame names are compared
  /// without a leading '/' (ROS 1 wrote "/velodyne" where ROS 2 writes "velodyne").
  void add(const std::string& parent, const std::string& child,
           const Eigen::Isometry3d& parent_T_child);

  /// target_T_source (a point of frame source expressed in frame target) along the chain of
  /// transforms that joins the two frames, each used in either direction; none without one.
  std::optional<Eigen::Isometry3d> lookup(const std::string& target,
                                          const std::string& source) const;

  /// "parent -> child" for each transform, one per line (for messages).
  std::string describe() const;
  bool empty() const { return edges_.empty(); }

 private:
  struct Edge {
    std::string parent, child;
    Eigen::Isometry3d parent_T_child;
  };
  std::vector<Edge> edges_;
};

}  // namespace socc::sensors
