#pragma once
// The ROS messages socc reads from bags, parsed from either serialization (ROS 1 or CDR):
// sensor_msgs/PointCloud2 and the vendors' raw packet messages. Parsers throw FormatError on
// bytes that do not hold the message.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bags/byte_view.hpp"
#include "bags/serialized_readers.hpp"
#include "socc/sensors/packet.hpp"

namespace socc::sensors::bags {

enum class Encoding { kRos1, kCdr };

enum class MessageKind {
  kPointCloud2,   // sensor_msgs/PointCloud2
  kVelodyneScan,  // velodyne_msgs/VelodyneScan: VelodynePacket[] (time stamp, uint8[1206] data)
  kPandarScan,    // pandar_msgs/PandarScan: PandarPacket[] (stamp, uint8[1500] data, uint32 size)
  kOusterPacket,  // ouster_ros / ouster_msgs / ouster_sensor_msgs PacketMsg: uint8[] buf
  kUnsupported,
};

/// The kind of a ROS 1 ("pkg/Name") or ROS 2 ("pkg/msg/Name") type name.
MessageKind messageKind(const std::string& type);
/// The type names socc reads, for error messages.
std::string supportedMessageTypes();

struct PointFieldMsg {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype =
      0;  // 1 INT8, 2 UINT8, 3 INT16, 4 UINT16, 5 INT32, 6 UINT32, 7 FLOAT32, 8 FLOAT64
  std::uint32_t count = 0;
};

struct PointCloud2Msg {
  MessageHeader header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::vector<PointFieldMsg> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  ByteView data;  // points into the serialized message
  bool is_dense = false;
};

PointCloud2Msg parsePointCloud2(ByteView message, Encoding encoding);

/// sensor_msgs/Imu ("sensor_msgs/Imu" or "sensor_msgs/msg/Imu"): not a LiDAR topic, read
/// beside one (socc/sensors/imu_stream.hpp).
bool isImuType(const std::string& type);

struct ImuMsg {
  MessageHeader header;
  std::array<double, 4> orientation{};  // x y z w
  std::array<double, 9> orientation_covariance{};
  std::array<double, 3> angular_velocity{};
  std::array<double, 9> angular_velocity_covariance{};
  std::array<double, 3> linear_acceleration{};
  std::array<double, 9> linear_acceleration_covariance{};
};

ImuMsg parseImu(ByteView message, Encoding encoding);

/// tf2_msgs/TFMessage: the transforms of /tf and /tf_static.
bool isTfMessageType(const std::string& type);

struct TransformMsg {  // geometry_msgs/TransformStamped: child_frame_id's pose in header.frame_id
  MessageHeader header;
  std::string child_frame_id;
  std::array<double, 3> translation{};
  std::array<double, 4> rotation{};  // x y z w
};

std::vector<TransformMsg> parseTfMessage(ByteView message, Encoding encoding);

/// Appends the UDP payloads of a packet message (kind != kPointCloud2) to out. Packets without
/// a stamp of their own (Ouster) get message_stamp_ns, the bag's receive time.
void appendPackets(MessageKind kind, ByteView message, Encoding encoding,
                   std::int64_t message_stamp_ns, std::vector<Packet>& out);

}  // namespace socc::sensors::bags
