#pragma once
// A PointCloud2 bag topic as scans, one scan per message (a packet topic goes through
// BagPacketSource and DecodedScanStream).
#include <memory>
#include <string>

#include "bags/bag_reader.hpp"
#include "socc/sensors/sensor_scan.hpp"

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

}  // namespace socc::sensors::bags
