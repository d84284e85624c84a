// The Velodyne decoder on arbitrary packets. The first byte picks the model (or detection), the
// return mode, and whether every third packet comes from a second sender (and which sender is
// selected); the rest is cut into 1206-byte data packets (the last one may be short), each
// stamped 1.3 ms after the previous. Return-mode bits 3 pick the models that need a calibration
// (HDL-64E with each return mode, VLS-128), given one written at start. The decoder must return
// or throw std::runtime_error, and every point it hands out must be finite and within the
// sensors' range.
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "socc/sensors/sensor_config.hpp"
#include "velodyne_model_cases.hpp"

namespace {

// Nominal-looking calibrations of the models that have none built in, removed at exit.
class Calibrations {
 public:
  Calibrations() {
    const std::string stem = "socc_fuzz_velodyne_" + std::to_string(::getpid());
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    hdl64_ = socc::sensors::test::writeYamlCalibration(
        dir / (stem + "_hdl64e.yaml"), socc::sensors::test::hdl64e(true).vert_deg, 0.002);
    vls128_ = socc::sensors::test::writeYamlCalibration(
        dir / (stem + "_vls128.yaml"), socc::sensors::test::vls128(false).vert_deg, 0.004);
  }
  ~Calibrations() {
    std::error_code ignored;
    std::filesystem::remove(hdl64_, ignored);
    std::filesystem::remove(vls128_, ignored);
  }
  Calibrations(const Calibrations&) = delete;
  Calibrations& operator=(const Calibrations&) = delete;
  const std::filesystem::path& hdl64() const { return hdl64_; }
  const std::filesystem::path& vls128() const { return vls128_; }

 private:
  std::filesystem::path hdl64_, vls128_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kModels[] = {"vlp16", "vlp32c", "hdl32e", ""};
  static const Calibrations calibrations;
  socc::sensors::SensorConfig config;
  const int model_bits = data[0] % 4;
  const int return_bits = (data[0] >> 2) % 4;
  if (return_bits < 3) {
    config.model = kModels[model_bits];
    config.returns = static_cast<socc::sensors::ReturnMode>(return_bits);  // all, strongest, last
  } else {
    config.model = model_bits < 3 ? "hdl64e" : "vls128";
    config.calibration = model_bits < 3 ? calibrations.hdl64() : calibrations.vls128();
    config.returns = static_cast<socc::sensors::ReturnMode>(model_bits % 3);
  }
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
