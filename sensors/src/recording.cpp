// openRecording: pcap captures through the packet decoders, bags through bag_recording.hpp.
#include "socc/sensors/recording.hpp"

#include <stdexcept>

#include "socc/sensors/bag_recording.hpp"
#include "socc/sensors/decoded_scan_stream.hpp"
#include "socc/sensors/pcap_source.hpp"

namespace socc::sensors {

std::unique_ptr<ScanStream> openRecording(const std::filesystem::path& file,
                                          const RecordingOptions& options) {
  if (!std::filesystem::exists(file)) throw std::runtime_error(file.string() + ": no such file");
  if (isBag(file)) return openBag(file, options);
  if (isPcap(file))
    return std::make_unique<DecodedScanStream>(openPcap(file, options.port),
                                               makeDecoder(options.sensor),
                                               "pcap " + file.filename().string());
  throw std::runtime_error(
      file.string() +
      ": not a recording socc reads (pcap / pcapng capture, ROS 1 .bag, ROS 2 .db3 or .mcap)");
}

}  // namespace socc::sensors
