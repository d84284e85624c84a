#pragma once
// Writes the scans of a ScanDirectory as socc::scan_t events (channel SOCC/SCAN/<robot_id>)
// into an LCM log file that lcm-logplayer can replay in real time.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "socc/scan_t.hpp"
#include "socc/tools/scan_directory.hpp"

namespace socc::tools {

struct ScanLogOptions {
  std::string robot_id = "robot1";
  double rate_hz = 10.0;         // scan rate when the directory has no times.txt
  std::int64_t start_utime = 0;  // timestamp of the first scan [us since epoch]
  bool progress = true;          // socc::ProgressBar on stderr
};

struct ScanLogSummary {
  std::size_t scans = 0;
  std::size_t points = 0;
  std::int64_t first_utime = 0;
  std::int64_t last_utime = 0;
};

/// Timestamps [us] of the scans: start_utime + (times.txt time - first time) when the
/// directory has times.txt, else start_utime + i / rate_hz. Throws std::invalid_argument on a
/// non-positive rate or decreasing times (log events must be in time order).
std::vector<std::int64_t> scanTimestamps(const ScanDirectory& dir, const ScanLogOptions& options);

/// The scan_t message of one frame.
scan_t toScanMessage(const ScanFrame& frame, const std::string& robot_id, std::int64_t seq,
                     std::int64_t utime);

/// Converts every scan into the log at out (overwritten). Throws std::runtime_error on I/O
/// or input errors; a partially written log is removed.
ScanLogSummary writeScanLog(const ScanDirectory& dir, const std::filesystem::path& out,
                            const ScanLogOptions& options);

}  // namespace socc::tools
