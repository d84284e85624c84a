// Ouster lidar packets of a 16-beam sensor in every profile, and metadata JSON files. Selector
// byte: value % 5 picks the profile (4: the rest is a metadata file), bits 4-5 the return
// selection, bit 6 keep_partial, bit 7 the nested (firmware 3) metadata layout. Errors must be
// exceptions.
#include <stdexcept>

#include "sensor_fuzz_input.hpp"
#include "socc/sensors/ouster_decoder.hpp"
#include "temp_file.hpp"
#include "vendor_packets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t selector = data[0];
  static const char* const profiles[] = {"LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG15_RFL8_NIR8",
                                         "RNG19_RFL8_SIG16_NIR16_DUAL"};
  socc::sensors::SensorConfig config;
  config.returns = static_cast<socc::sensors::ReturnMode>((selector >> 4) & 3);
  config.keep_partial = selector & 0x40;
  try {
    if (selector % 5 == 4) {
      const socc::fuzz::TempFile json(data + 1, size - 1, ".json");
      config.calibration = json.path();
      socc::sensors::makeOusterDecoder(config);
      return 0;
    }
    socc::sensors::test_packets::OusterSpec spec;
    spec.profile = profiles[selector % 5];
    const std::string md = socc::sensors::test_packets::ousterMetadata(spec, selector & 0x80);
    const socc::fuzz::TempFile json(reinterpret_cast<const std::uint8_t*>(md.data()), md.size(),
                                    ".json");
    config.calibration = json.path();
    const auto decoder = socc::sensors::makeOusterDecoder(config);
    socc::fuzz::decodeAll(*decoder, socc::fuzz::splitPackets(data + 1, size - 1), 16);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
