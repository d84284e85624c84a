#include "bags/bag_reader.hpp"
namespace socc::sensors::bags {
std::unique_ptr<BagReader> openMcap(const std::filesystem::path& file) {
  throw std::runtime_error(file.string() + ": MCAP not yet");
}
}  // namespace socc::sensors::bags
