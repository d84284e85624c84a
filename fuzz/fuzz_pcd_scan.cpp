// PCD input of socc-to-lcmlog: header check, then PCL's reader; errors must be exceptions.
#include <stdexcept>

#include "socc/tools/scan_directory.hpp"
#include "temp_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const socc::fuzz::TempFile file(data, size, ".pcd");
  try {
    socc::tools::readPcdScan(file.path());
  } catch (const std::runtime_error&) {
  }
  return 0;
}
