#pragma once
// Paths of the real recordings the bag tests read; a test skips only when the data folder is
// absent (scripts/run_tests.sh fails on a skip when it is present).
#include <filesystem>

namespace socc::sensors::test {

inline std::filesystem::path rawSensors() {
  return std::filesystem::path(SOCC_SHARED_DATA_DIR) / "raw_sensors";
}
inline std::filesystem::path sharedData() {
  return std::filesystem::path(SOCC_SHARED_DATA_DIR);
}

}  // namespace socc::sensors::test

#define SOCC_REQUIRE_DATA(path)                                              \
  do {                                                                       \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << (path) << " absent"; \
  } while (false)
