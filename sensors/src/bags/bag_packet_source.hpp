#pragma once
// The UDP payloads carried by a packet topic of a bag (velodyne_msgs/VelodyneScan,
// pandar_msgs/PandarScan, Ouster PacketMsg), in stored order, for a ScanDecoder.
#include <deque>
#include <memory>

#include "bags/bag_reader.hpp"
#include "socc/sensors/packet.hpp"

namespace socc::sensors::bags {

class BagPacketSource : public PacketSource {
 public:
  /// reader is switched to topic, which must be a packet topic.
  BagPacketSource(std::unique_ptr<BagReader> reader, std::size_t topic);

  std::optional<Packet> next() override;
  /// The reader's problems and the messages dropped as malformed.
  std::string problems() const override;

 private:
  std::unique_ptr<BagReader> reader_;
  MessageKind kind_;
  Encoding encoding_;
  std::deque<Packet> pending_;
  std::uint64_t malformed_messages_ = 0;
  std::string first_error_;
};

}  // namespace socc::sensors::bags
