#pragma once
// The two ways a bag topic becomes scans: a PointCloud2 topic one scan per message, a packet
// topic through a ScanDecoder.
#include <deque>
#include <memory>
#include <string>

#include "bags/bag_packet_source.hpp"
#include "bags/bag_reader.hpp"
#include "socc/sensors/scan_decoder.hpp"

namespace socc::sensors::bags {

class PointCloudScanStream : public ScanStream {
 public:
  /// reader is switched to topic (a sensor_msgs/PointCloud2 topic); source names the scans.
  PointCloudScanStream(std::unique_ptr<BagReader> reader, std::size_t topic, std::string source);

  std::optional<SensorScan> next() override;
  /// The reader's problems, dropped messages, clouds without points, unusable time fields.
  std::string problems() const override;

 private:
  std::unique_ptr<BagReader> reader_;
  Encoding encoding_;
  std::string source_;
  std::int64_t seq_ = 0;
  std::uint64_t malformed_ = 0;
  std::string first_error_;
  std::uint64_t empty_ = 0;
  std::uint64_t untimed_ = 0;
  std::string first_time_problem_;
};

class PacketScanStream : public ScanStream {
 public:
  PacketScanStream(std::unique_ptr<PacketSource> packets, std::unique_ptr<ScanDecoder> decoder,
                   std::string source);

  std::optional<SensorScan> next() override;
  /// The packet source's problems and the decoder's counts of skipped packets and sweeps.
  std::string problems() const override;

 private:
  std::unique_ptr<PacketSource> packets_;
  std::unique_ptr<ScanDecoder> decoder_;
  std::string source_;
  std::deque<SensorScan> ready_;
  bool ended_ = false;
  std::int64_t seq_ = 0;
};

}  // namespace socc::sensors::bags
