#pragma once
// An IMU as a recording holds it: sensor_msgs/Imu messages of a bag, in stored order. odom_client
// takes the attitude (orientation) as its gravity reference (odom_client/README.md "Gravity
// reference"); the rates are kept as recorded.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace socc::sensors {

struct ImuSample {
  std::int64_t stamp_ns = 0;  // the message's header stamp
  std::string frame_id;       // the message's header frame_id: the IMU's frame
  /// The IMU frame's orientation in its world frame (z up, ENU as REP 103/145 say); none when
  /// the message carries none (orientation_covariance[0] == -1) or an unusable quaternion.
  std::optional<Eigen::Quaterniond> orientation;
  /// As recorded: about the world's x, y, z [rad^2]; all zero: not known (REP 145).
  Eigen::Matrix3d orientation_covariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();     // [rad/s], IMU frame
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // [m/s^2], IMU frame
};

class ImuStream {
 public:
  virtual ~ImuStream() = default;
  /// The next sample, or nullopt at the end.
  virtual std::optional<ImuSample> next() = 0;
  /// Counted problems so far (damaged or malformed messages), one line per kind; empty if none.
  virtual std::string problems() const { return {}; }
};

/// The sensor_msgs/Imu topic of a bag (ROS 1 .bag, ROS 2 .db3 or its folder, .mcap); topic empty:
/// the bag's only Imu topic. Throws std::runtime_error naming the bag and listing its topics
/// when there is no such topic, or several and none chosen.
std::unique_ptr<ImuStream> openImuTopic(const std::filesystem::path& bag, const std::string& topic);

}  // namespace socc::sensors
