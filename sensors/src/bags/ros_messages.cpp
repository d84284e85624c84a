#include "bags/ros_messages.hpp"

#include <array>

namespace socc::sensors::bags {

namespace {

constexpr std::size_t kVelodynePacketBytes = 1206;
constexpr std::size_t kPandarPacketBytes = 1500;

/// "pkg/msg/Name" -> "pkg/Name"; ROS 1 names are unchanged.
std::string ros1TypeName(const std::string& type) {
  const auto pos = type.find("/msg/");
  return pos == std::string::npos ? type : type.substr(0, pos) + "/" + type.substr(pos + 5);
}

// read(reader) on a reader of the message's serialization: each parser is written once.
template <class Read>
auto parseAs(ByteView message, Encoding encoding, Read read) {
  if (encoding == Encoding::kRos1) {
    Ros1Reader r(message);
    return read(r);
  }
  CdrReader r(message);
  return read(r);
}

template <class Reader>
PointCloud2Msg readPointCloud2(Reader& r) {
  PointCloud2Msg m;
  m.header = r.header();
  m.height = r.template read<std::uint32_t>();
  m.width = r.template read<std::uint32_t>();
  const std::uint32_t fields = r.sequenceLength(13);
  m.fields.resize(fields);
  for (PointFieldMsg& f : m.fields) {
    f.name = r.string();
    f.offset = r.template read<std::uint32_t>();
    f.datatype = r.template read<std::uint8_t>();
    f.count = r.template read<std::uint32_t>();
  }
  m.is_bigendian = r.template read<std::uint8_t>() != 0;
  m.point_step = r.template read<std::uint32_t>();
  m.row_step = r.template read<std::uint32_t>();
  m.data = r.bytes(r.sequenceLength(1));
  m.is_dense = r.template read<std::uint8_t>() != 0;
  return m;
}

template <class Reader, std::size_t N>
void readDoubles(Reader& r, std::array<double, N>& out) {
  for (double& v : out) v = r.template read<double>();
}

template <class Reader>
ImuMsg readImu(Reader& r) {
  ImuMsg m;
  m.header = r.header();
  readDoubles(r, m.orientation);
  readDoubles(r, m.orientation_covariance);
  readDoubles(r, m.angular_velocity);
  readDoubles(r, m.angular_velocity_covariance);
  readDoubles(r, m.linear_acceleration);
  readDoubles(r, m.linear_acceleration_covariance);
  return m;
}

template <class Reader>
std::vector<TransformMsg> readTfMessage(Reader& r) {
  // Header (stamp, frame_id), child_frame_id and 7 float64: at least 64 bytes each.
  std::vector<TransformMsg> out(r.sequenceLength(64));
  for (TransformMsg& t : out) {
    t.header = r.header();
    t.child_frame_id = r.string();
    readDoubles(r, t.translation);
    readDoubles(r, t.rotation);
  }
  return out;
}

Packet packetOf(std::int64_t stamp_ns, ByteView bytes) {
  Packet p;
  p.stamp_ns = stamp_ns;
  p.data.assign(bytes.data, bytes.data + bytes.size);
  return p;
}

template <class Reader>
void readVelodyneScan(Reader& r, std::vector<Packet>& out) {
  r.header();
  const std::uint32_t n = r.sequenceLength(8 + kVelodynePacketBytes);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::int64_t stamp = r.time();
    out.push_back(packetOf(stamp, r.bytes(kVelodynePacketBytes)));
  }
}

template <class Reader>
void readPandarScan(Reader& r, std::vector<Packet>& out) {
  r.header();
  const std::uint32_t n = r.sequenceLength(8 + kPandarPacketBytes + 4);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::int64_t stamp = r.time();
    const ByteView data = r.bytes(kPandarPacketBytes);
    const auto size = r.template read<std::uint32_t>();
    if (size > kPandarPacketBytes) {
      throw FormatError("PandarPacket of " + std::to_string(size) + " bytes (at most 1500)");
    }
    out.push_back(packetOf(stamp, data.sub(0, size)));
  }
}

template <class Reader>
void readOusterPacket(Reader& r, std::int64_t stamp_ns, std::vector<Packet>& out) {
  out.push_back(packetOf(stamp_ns, r.bytes(r.sequenceLength(1))));
}

template <class Reader>
void readPackets(MessageKind kind, Reader& r, std::int64_t stamp_ns, std::vector<Packet>& out) {
  switch (kind) {
    case MessageKind::kVelodyneScan:
      return readVelodyneScan(r, out);
    case MessageKind::kPandarScan:
      return readPandarScan(r, out);
    case MessageKind::kOusterPacket:
      return readOusterPacket(r, stamp_ns, out);
    default:
      throw FormatError("not a packet message");
  }
}

}  // namespace

MessageKind messageKind(const std::string& type) {
  const std::string t = ros1TypeName(type);
  if (t == "sensor_msgs/PointCloud2") return MessageKind::kPointCloud2;
  if (t == "velodyne_msgs/VelodyneScan") return MessageKind::kVelodyneScan;
  if (t == "pandar_msgs/PandarScan") return MessageKind::kPandarScan;
  if (t == "ouster_ros/PacketMsg" || t == "ouster_msgs/PacketMsg" ||
      t == "ouster_sensor_msgs/PacketMsg") {
    return MessageKind::kOusterPacket;
  }
  return MessageKind::kUnsupported;
}

std::string supportedMessageTypes() {
  return "sensor_msgs/PointCloud2, velodyne_msgs/VelodyneScan, pandar_msgs/PandarScan, "
         "ouster_ros|ouster_msgs|ouster_sensor_msgs/PacketMsg";
}

PointCloud2Msg parsePointCloud2(ByteView message, Encoding encoding) {
  return parseAs(message, encoding, [](auto& r) { return readPointCloud2(r); });
}

bool isImuType(const std::string& type) {
  return ros1TypeName(type) == "sensor_msgs/Imu";
}

ImuMsg parseImu(ByteView message, Encoding encoding) {
  return parseAs(message, encoding, [](auto& r) { return readImu(r); });
}

bool isTfMessageType(const std::string& type) {
  return ros1TypeName(type) == "tf2_msgs/TFMessage";
}

std::vector<TransformMsg> parseTfMessage(ByteView message, Encoding encoding) {
  return parseAs(message, encoding, [](auto& r) { return readTfMessage(r); });
}

void appendPackets(MessageKind kind, ByteView message, Encoding encoding,
                   std::int64_t message_stamp_ns, std::vector<Packet>& out) {
  // All of a message's packets or none: a damaged message is one counted drop.
  std::vector<Packet> packets = parseAs(message, encoding, [&](auto& r) {
    std::vector<Packet> read;
    readPackets(kind, r, message_stamp_ns, read);
    return read;
  });
  for (Packet& p : packets) out.push_back(std::move(p));
}

}  // namespace socc::sensors::bags
