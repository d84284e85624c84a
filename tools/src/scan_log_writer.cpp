#include "socc/tools/scan_log_writer.hpp"

#include <cmath>
#include <stdexcept>

#include "socc/channels.hpp"
#include "socc/progress_bar.hpp"
#include "socc/tools/scan_log_file.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::tools {
namespace fs = std::filesystem;

std::vector<std::int64_t> scanTimestamps(const ScanDirectory& dir, const ScanLogOptions& options) {
  std::vector<std::int64_t> stamps;
  stamps.reserve(dir.scans.size());
  if (dir.scan_times.empty()) {
    if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz))
      throw std::invalid_argument("rate must be a positive number of Hz");
    const double period_us = 1e6 / options.rate_hz;
    for (std::size_t i = 0; i < dir.scans.size(); ++i)
      stamps.push_back(options.start_utime + std::llround(static_cast<double>(i) * period_us));
    return stamps;
  }
  for (std::size_t i = 0; i < dir.scans.size(); ++i) {
    const double dt = dir.scan_times[i] - dir.scan_times.front();
    if (i > 0 && dir.scan_times[i] < dir.scan_times[i - 1])
      throw std::invalid_argument("times.txt: time of " + dir.scans[i].filename().string() +
                                  " is before the previous scan's");
    stamps.push_back(options.start_utime + std::llround(dt * 1e6));
  }
  return stamps;
}

scan_t toScanMessage(const ScanFrame& frame, const std::string& robot_id, std::int64_t seq,
                     std::int64_t utime) {
  const LabeledCloud& c = frame.cloud;
  scan_t msg;
  msg.utime = utime;
  msg.robot_id = robot_id;
  msg.seq = seq;
  msg.num_points = static_cast<std::int32_t>(c.size());
  wire::pointsToRows(c.points, msg.xyz);
  msg.num_intensities = static_cast<std::int32_t>(frame.intensity.size());
  msg.intensity = frame.intensity;
  msg.num_labels = static_cast<std::int32_t>(c.labels.size());
  msg.label.assign(c.labels.begin(), c.labels.end());
  msg.num_times = static_cast<std::int32_t>(c.times.size());
  msg.time = c.times;
  return msg;
}

ScanLogSummary writeScanLog(const ScanDirectory& dir, const fs::path& out,
                            const ScanLogOptions& options) {
  const std::vector<std::int64_t> stamps = scanTimestamps(dir, options);
  const std::string channel = channels::scan(options.robot_id);
  ScanLogSummary summary;
  ScanLogFile log(out);
  ProgressBar bar("socc-to-lcmlog", dir.scans.size(), options.progress);
  for (std::size_t i = 0; i < dir.scans.size(); ++i) {
    const scan_t msg =
        toScanMessage(loadScan(dir, i), options.robot_id, static_cast<std::int64_t>(i), stamps[i]);
    log.append(channel, msg, stamps[i], dir.scans[i].string() + ": scan");
    summary.points += static_cast<std::size_t>(msg.num_points);
    bar.tick(std::to_string(msg.num_points) + " points");
  }
  log.finish();
  summary.scans = dir.scans.size();
  if (!stamps.empty()) {
    summary.first_utime = stamps.front();
    summary.last_utime = stamps.back();
  }
  return summary;
}

}  // namespace socc::tools
