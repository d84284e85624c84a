#include "socc/tools/recording_log_writer.hpp"

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "socc/channels.hpp"
#include "socc/progress_bar.hpp"
#include "socc/tools/sensor_scan_message.hpp"

namespace socc::tools {
namespace fs = std::filesystem;

ScanLogSummary writeRecordingLog(sensors::ScanStream& stream, const fs::path& out,
                                 const std::string& robot_id, bool progress) {
  const std::string channel = channels::scan(robot_id);
  ScanLogSummary summary;
  try {
    lcm::LogFile log(out.string(), "w");
    if (!log.good()) throw std::runtime_error(out.string() + ": cannot open for writing");
    ProgressBar bar("socc-to-lcmlog", 0, progress);
    std::vector<std::uint8_t> buf;
    std::int64_t last_event = 0;
    while (std::optional<sensors::SensorScan> sweep = stream.next()) {
      const scan_t msg = toScanMessage(*sweep, robot_id);
      buf.resize(static_cast<std::size_t>(msg.getEncodedSize()));
      if (msg.encode(buf.data(), 0, static_cast<int>(buf.size())) != static_cast<int>(buf.size()))
        throw std::runtime_error("sweep " + std::to_string(sweep->seq) + " does not encode");
      lcm::LogEvent event;
      event.eventnum = static_cast<std::int64_t>(summary.scans);
      event.timestamp = std::max(sweepEndUtime(*sweep), last_event);  // log events in time order
      last_event = event.timestamp;
      event.channel = channel;
      event.datalen = static_cast<std::int32_t>(buf.size());
      event.data = buf.data();
      if (log.writeEvent(&event) != 0) throw std::runtime_error(out.string() + ": write error");
      if (summary.scans == 0) summary.first_utime = msg.utime;
      summary.last_utime = msg.utime;
      ++summary.scans;
      summary.points += static_cast<std::size_t>(msg.num_points);
      bar.tick(std::to_string(msg.num_points) + " points");
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove(out, ignored);  // never leave a truncated log that looks complete
    throw;
  }
  return summary;
}

}  // namespace socc::tools
