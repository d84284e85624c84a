#pragma once
// The scans of a source, each prepared (prepareScan: range filter, labels, point times) in a
// worker thread while the caller registers the one before: preprocessing is off the frame's
// critical path (odom_client/README.md "Pipeline").
#include <cstdint>
#include <future>
#include <optional>
#include <string>

#include "socc/odom/odom_config.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/scan_source.hpp"

namespace socc::odom {

struct PreparedInput {
  std::int64_t seq = 0;
  std::string name;                  // the scan's, for messages
  bool skipped = false;              // seq <= skip_until_seq: not prepared
  std::optional<PreparedScan> scan;  // none: skipped, or unusable (problem says why)
  std::string problem;
};

class ScanPreparer {
 public:
  /// Scans of source up to skip_until_seq are passed on unprepared (integrated before a restart).
  ScanPreparer(ScanSource& source, const OdomConfig& config, std::int64_t skip_until_seq);
  ~ScanPreparer();  // waits for the worker, which uses the source
  ScanPreparer(const ScanPreparer&) = delete;
  ScanPreparer& operator=(const ScanPreparer&) = delete;

  /// The next scan, or nullopt at the end of the source. Rethrows the source's errors.
  std::optional<PreparedInput> next();

 private:
  std::optional<PreparedInput> readAndPrepare() const;

  ScanSource& source_;
  OdomConfig config_;
  std::int64_t skip_until_seq_;
  std::future<std::optional<PreparedInput>> pending_;
};

}  // namespace socc::odom
