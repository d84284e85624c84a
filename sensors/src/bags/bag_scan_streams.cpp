#include "bags/bag_scan_streams.hpp"

#include "bags/pointcloud2_scan.hpp"

namespace socc::sensors::bags {

PointCloudScanStream::PointCloudScanStream(std::unique_ptr<BagReader> reader, std::size_t topic,
                                           std::string source)
    : reader_(std::move(reader)), source_(std::move(source)) {
  encoding_ = reader_->topics().at(topic).encoding.value();
  reader_->select(topic);
}

std::optional<SensorScan> PointCloudScanStream::next() {
  while (std::optional<BagMessage> m = reader_->next()) {
    PointCloud2Conversion c;
    try {
      c = convertPointCloud2(parsePointCloud2(ByteView(m->data), encoding_), m->stamp_ns);
    } catch (const FormatError& e) {
      if (malformed_++ == 0) first_error_ = e.what();
      continue;
    }
    if (!c.time_problem.empty() && untimed_++ == 0) first_time_problem_ = c.time_problem;
    if (c.scan.points.empty()) {
      ++empty_;
      continue;
    }
    c.scan.seq = seq_++;
    c.scan.source = source_;
    return std::move(c.scan);
  }
  return std::nullopt;
}

std::string PointCloudScanStream::problems() const {
  std::string p = reader_->problems();
  if (malformed_ > 0) {
    p += std::to_string(malformed_) +
         " malformed PointCloud2 messages dropped (first: " + first_error_ + ")\n";
  }
  if (empty_ > 0) p += std::to_string(empty_) + " PointCloud2 messages without a valid point\n";
  if (untimed_ > 0) {
    p += std::to_string(untimed_) + " clouds without point times (first: " + first_time_problem_ +
         ")\n";
  }
  return p;
}

}  // namespace socc::sensors::bags
