// The Velodyne decoder on arbitrary packets. The first byte picks the model (or detection), the
// return mode, and whether every third packet comes from a second sender (and which sender is
// selected); the rest is cut into 1206-byte data packets (the last one may be short), each
// stamped 1.3 ms after the previous. The decoder must return or throw std::runtime_error,
// and every point it hands out must be finite and within the sensors' range.
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "socc/sensors/sensor_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kModels[] = {"vlp16", "vlp32c", "hdl32e", ""};
  socc::sensors::SensorConfig config;
  config.model = kModels[data[0] % 4];
  config.returns =
      static_cast<socc::sensors::ReturnMode>((data[0] >> 2) % 3);  // all, strongest, last
  config.keep_partial = (data[0] & 0x20) != 0;
  config.cut_azimuth_deg = (data[0] >> 6) * 90.0;
  const bool two_senders = (data[0] & 0x10) != 0;
  if (two_senders && config.keep_partial) config.sensor_address = "10.0.0.2";
  config.notify = [](const std::string&) {};
  try {
    std::unique_ptr<socc::sensors::ScanDecoder> decoder = socc::sensors::makeDecoder(config);
    std::vector<socc::sensors::SensorScan> out;
    std::int64_t stamp = 1'000'000'000;
    std::size_t index = 0;
    for (std::size_t at = 1; at < size; at += 1206, stamp += 1'327'000, ++index) {
      socc::sensors::Packet p;
      p.stamp_ns = stamp;
      p.source_ipv4 = two_senders && index % 3 == 2 ? 0x0A000002 : 0x0A000001;
      p.data.assign(data + at, data + std::min(size, at + 1206));
      decoder->feed(p, out);
    }
    decoder->flush(out);
    for (const socc::sensors::SensorScan& s : out)
      for (std::size_t i = 0; i < s.size(); ++i)
        if (!s.points[i].allFinite() || s.points[i].norm() > 300.0f || !std::isfinite(s.time[i]) ||
            s.time[i] < 0.0f)
          std::abort();  // a garbage point
  } catch (const std::runtime_error&) {
  }
  return 0;
}
