// The YAML configuration loaders (grid: socc::map::loadMapConfig; server:
// socc::service::loadServerConfig) on arbitrary text; both must only throw std::runtime_error.
#include <stdexcept>

#include "service/service_config.hpp"
#include "socc/map/map_config.hpp"
#include "temp_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const socc::fuzz::TempFile file(data + 1, size - 1, ".yaml");
  try {
    if (data[0] % 2 == 0) {
      const socc::map::MapConfig config = socc::map::loadMapConfig(file.path());
      socc::map::validate(config);
    } else {
      socc::service::loadServerConfig(file.path());
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
