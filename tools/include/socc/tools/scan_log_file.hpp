#pragma once
// An LCM log being written with scan_t events, for socc-to-lcmlog's writers (directories of
// scans, recordings). Removed again on destruction unless finished: a failed conversion never
// leaves a truncated log that looks complete.
#include <cstdint>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "socc/scan_t.hpp"

namespace socc::tools {

class ScanLogFile {
 public:
  /// Opens (overwrites) path; throws std::runtime_error when it cannot.
  explicit ScanLogFile(std::filesystem::path path);
  ~ScanLogFile();
  ScanLogFile(const ScanLogFile&) = delete;
  ScanLogFile& operator=(const ScanLogFile&) = delete;

  /// Appends msg on channel as the next event, at timestamp [us] (lcm-logplayer keeps the gaps).
  /// Throws std::runtime_error "<what> does not encode" or a write error.
  void append(const std::string& channel, const scan_t& msg, std::int64_t timestamp,
              const std::string& what);
  /// Keeps the log: call after the last append.
  void finish();

 private:
  std::filesystem::path path_;
  std::unique_ptr<lcm::LogFile> log_;
  std::vector<std::uint8_t> buf_;  // reused: scans are megabytes
  std::int64_t events_ = 0;
  bool finished_ = false;
};

}  // namespace socc::tools
