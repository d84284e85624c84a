#pragma once
// Paths of the real recordings in ../shared/data/raw_sensors (tests skip only when the folder
// is absent).
#include <filesystem>
#include <string>

namespace socc::sensors::test {

inline std::filesystem::path rawSensors() {
  return std::filesystem::path(SOCC_SHARED_DATA_DIR) / "raw_sensors";
}
inline std::filesystem::path vlp16Dir() {
  return rawSensors() / "01_velodyne_vlp16_veloview";
}
inline std::filesystem::path vlp16Pcap() {
  return vlp16Dir() / "vlp-16-test-90deg-1-50-frames.pcap";
}
inline std::filesystem::path vlp16Xml() {
  return vlp16Dir() / "VLP-16.xml";
}
inline std::filesystem::path vlp32cDir() {
  return rawSensors() / "03_velodyne_vlp32c_nebula_db3";
}

}  // namespace socc::sensors::test

#define SOCC_REQUIRE_RAW_SENSORS()                                       \
  do {                                                                   \
    if (!std::filesystem::exists(socc::sensors::test::rawSensors()))     \
      GTEST_SKIP() << socc::sensors::test::rawSensors() << " is absent"; \
  } while (false)
