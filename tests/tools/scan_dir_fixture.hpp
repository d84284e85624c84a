#pragma once
// Test helpers: a per-test temporary directory and reading an LCM log back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "socc/scan_t.hpp"

namespace socc::tools::test {

class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("socc_test_tools_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

struct LoggedScan {
  std::string channel;
  std::int64_t timestamp = 0;
  scan_t scan;
};

/// Reads every event of an LCM log and decodes it as scan_t (ADD_FAILURE when it does not).
inline std::vector<LoggedScan> readScanLog(const std::filesystem::path& file) {
  std::vector<LoggedScan> out;
  lcm::LogFile log(file.string(), "r");
  EXPECT_TRUE(log.good()) << file;
  if (!log.good()) return out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    LoggedScan s;
    s.channel = e->channel;
    s.timestamp = e->timestamp;
    EXPECT_EQ(s.scan.decode(e->data, 0, e->datalen), e->datalen) << "event " << e->eventnum;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace socc::tools::test
