// Hesai packets (PandarXT32, Pandar40P, Pandar64) and angle-correction CSVs. Selector byte:
// bits 0-1 the model (3: the rest is a CSV file for the model of bits 2-3), bits 4-5 the
// return selection, bit 6 keep_partial, bit 7 a cut at 180 deg. Errors must be exceptions.
#include <stdexcept>

#include "sensor_fuzz_input.hpp"
#include "socc/sensors/hesai_decoder.hpp"
#include "temp_file.hpp"
#include "vendor_packets.hpp"

namespace {

// The calibration files of the models that need one, written once per process.
const socc::fuzz::TempFile& calibration(int lasers) {
  static const std::string csv40 = socc::sensors::test_packets::hesaiCalibrationCsv(40);
  static const std::string csv64 = socc::sensors::test_packets::hesaiCalibrationCsv(64);
  static const socc::fuzz::TempFile file40(reinterpret_cast<const std::uint8_t*>(csv40.data()),
                                           csv40.size(), ".csv");
  static const socc::fuzz::TempFile file64(reinterpret_cast<const std::uint8_t*>(csv64.data()),
                                           csv64.size(), ".csv");
  return lasers == 40 ? file40 : file64;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t selector = data[0];
  static const char* const models[] = {"pandarxt32", "pandar40p", "pandar64"};
  socc::sensors::SensorConfig config;
  config.returns = static_cast<socc::sensors::ReturnMode>((selector >> 4) & 3);
  config.keep_partial = selector & 0x40;
  config.cut_azimuth_deg = selector & 0x80 ? 180.0 : 0.0;
  try {
    if ((selector & 3) == 3) {
      config.model = models[((selector >> 2) & 3) % 3];
      const socc::fuzz::TempFile csv(data + 1, size - 1, ".csv");
      config.calibration = csv.path();
      socc::sensors::makeHesaiDecoder(config);
      return 0;
    }
    config.model = models[selector & 3];
    if (config.model == "pandar40p") config.calibration = calibration(40).path();
    if (config.model == "pandar64") config.calibration = calibration(64).path();
    const auto decoder = socc::sensors::makeHesaiDecoder(config);
    socc::fuzz::decodeAll(*decoder, socc::fuzz::splitPackets(data + 1, size - 1), 64);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
