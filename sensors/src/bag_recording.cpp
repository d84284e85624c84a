// Bags as scan streams (bag_recording.hpp): the container by extension or folder layout, the
// topic by name or as the only LiDAR topic, PointCloud2 directly, packets through makeDecoder.
#include "socc/sensors/bag_recording.hpp"

#include <stdexcept>

#include "bags/bag_packet_source.hpp"
#include "bags/bag_reader.hpp"
#include "bags/bag_scan_streams.hpp"
#include "bags/bag_topics.hpp"
#include "socc/sensors/decoded_scan_stream.hpp"

namespace socc::sensors {

namespace fs = std::filesystem;

bool isBag(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    if (fs::exists(file / "metadata.yaml", ec)) return true;
    for (const fs::directory_entry& e : fs::directory_iterator(file, ec)) {
      if (bags::hasBagExtension(e.path()) && e.path().extension() != ".bag") return true;
    }
    return false;
  }
  return bags::hasBagExtension(file);
}

std::unique_ptr<ScanStream> openBag(const fs::path& file, const RecordingOptions& options) {
  if (!options.sensor.sensor_address.empty())
    throw std::runtime_error(file.string() +
                             ": a bag keeps no sender address (the sensor address selects among "
                             "the senders of a pcap or a live port); choose the topic instead");
  std::unique_ptr<bags::BagReader> reader = bags::openBagReader(file);
  const std::size_t topic = bags::chooseTopic(*reader, options.topic, file);
  const bags::TopicInfo info = reader->topics()[topic];
  const std::string source = "bag " + file.filename().string() + " " + info.name;
  if (bags::messageKind(info.type) == bags::MessageKind::kPointCloud2) {
    return std::make_unique<bags::PointCloudScanStream>(std::move(reader), topic, source);
  }
  std::unique_ptr<ScanDecoder> decoder = makeDecoder(options.sensor);
  return std::make_unique<DecodedScanStream>(
      std::make_unique<bags::BagPacketSource>(std::move(reader), topic), std::move(decoder),
      source);
}

}  // namespace socc::sensors
