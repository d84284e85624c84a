// Serialized ROS messages as bags carry them: the first byte picks the serialization (bit 0:
// CDR or ROS 1) and the message (bits 1-2: PointCloud2, VelodyneScan, PandarScan, Ouster
// PacketMsg; bit 3 set: sensor_msgs/Imu, or with bit 4 tf2_msgs/TFMessage). A parser either
// returns or throws FormatError; a PointCloud2 that parses is converted to a scan, whose points
// must all be finite.
#include <cmath>
#include <cstdlib>

#include "bags/pointcloud2_scan.hpp"
#include "bags/ros_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace bags = socc::sensors::bags;
  if (size == 0) return 0;
  const bags::Encoding encoding = data[0] & 1 ? bags::Encoding::kRos1 : bags::Encoding::kCdr;
  const bags::MessageKind kinds[] = {
      bags::MessageKind::kPointCloud2, bags::MessageKind::kVelodyneScan,
      bags::MessageKind::kPandarScan, bags::MessageKind::kOusterPacket};
  const bags::MessageKind kind = kinds[(data[0] >> 1) & 3];
  const bags::ByteView message(data + 1, size - 1);
  try {
    if (data[0] & 8) {
      if (data[0] & 16)
        bags::parseTfMessage(message, encoding);
      else
        bags::parseImu(message, encoding);
    } else if (kind == bags::MessageKind::kPointCloud2) {
      const bags::PointCloud2Conversion c =
          bags::convertPointCloud2(bags::parsePointCloud2(message, encoding), 0);
      for (const Eigen::Vector3f& p : c.scan.points) {
        if (!p.allFinite()) std::abort();  // never a scan with garbage points
      }
      for (const float t : c.scan.time) {
        if (!std::isfinite(t) || t < 0.f) std::abort();
      }
    } else {
      std::vector<socc::sensors::Packet> packets;
      bags::appendPackets(kind, message, encoding, 0, packets);
    }
  } catch (const bags::FormatError&) {
  }
  return 0;
}
