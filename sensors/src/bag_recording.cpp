// Placeholder until the bag readers land: the interface is in bag_recording.hpp.
#include "socc/sensors/bag_recording.hpp"

#include <stdexcept>

namespace socc::sensors {

bool isBag(const std::filesystem::path&) {
  return false;
}

std::unique_ptr<ScanStream> openBag(const std::filesystem::path& file, const RecordingOptions&) {
  throw std::runtime_error(file.string() + ": bags are not supported yet");
}

}  // namespace socc::sensors
