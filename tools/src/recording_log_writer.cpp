#include "socc/tools/recording_log_writer.hpp"

#include <algorithm>

#include "socc/channels.hpp"
#include "socc/progress_bar.hpp"
#include "socc/tools/scan_log_file.hpp"
#include "socc/tools/sensor_scan_message.hpp"

namespace socc::tools {
namespace fs = std::filesystem;

ScanLogSummary writeRecordingLog(sensors::ScanStream& stream, const fs::path& out,
                                 const std::string& robot_id, bool progress) {
  const std::string channel = channels::scan(robot_id);
  ScanLogSummary summary;
  ScanLogFile log(out);
  ProgressBar bar("socc-to-lcmlog", 0, progress);
  std::int64_t last_event = 0;
  while (std::optional<sensors::SensorScan> sweep = stream.next()) {
    const scan_t msg = toScanMessage(*sweep, robot_id);
    last_event = std::max(sweepEndUtime(*sweep), last_event);  // log events in time order
    log.append(channel, msg, last_event, "sweep " + std::to_string(sweep->seq));
    if (summary.scans == 0) summary.first_utime = msg.utime;
    summary.last_utime = msg.utime;
    ++summary.scans;
    summary.points += static_cast<std::size_t>(msg.num_points);
    bar.tick(std::to_string(msg.num_points) + " points");
  }
  log.finish();
  return summary;
}

}  // namespace socc::tools
