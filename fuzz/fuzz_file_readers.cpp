// The KITTI / TUM file readers of socc_shared (and gravity.txt) on arbitrary file content. The
// first byte picks the reader; every reader must either return or throw std::runtime_error.
#include <stdexcept>

#include "socc/gravity_file.hpp"
#include "socc/kitti_io.hpp"
#include "temp_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const socc::fuzz::TempFile file(data + 1, size - 1);
  try {
    switch (data[0] % 9) {
      case 0: {
        std::vector<float> reflectance;
        socc::readKittiBin(file.path(), &reflectance);
        break;
      }
      case 1:
        socc::readSemanticKittiLabels(file.path());
        break;
      case 2:
        socc::readKittiPoses(file.path());
        break;
      case 3:
        socc::readKittiCalibTr(file.path());
        break;
      case 4: {
        std::vector<double> stamps;
        socc::readTumPoses(file.path(), &stamps);
        break;
      }
      case 5:
        socc::readTimes(file.path());
        break;
      case 6:
        socc::readXyzBin(file.path());
        break;
      case 7:
        socc::readFloatBin(file.path());
        break;
      default:
        socc::readGravityFile(file.path());
        break;
    }
  } catch (const std::runtime_error&) {
    // The documented way to reject bad input.
  }
  return 0;
}
