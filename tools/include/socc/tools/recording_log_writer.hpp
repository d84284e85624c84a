#pragma once
// Writes the sweeps of a recording (pcap capture or bag, through sensors::openRecording) as
// socc::scan_t events of an LCM log, stamped with the recording's own clock so that
// lcm-logplayer replays them at the recorded pace.
#include <filesystem>
#include <string>

#include "socc/sensors/sensor_scan.hpp"
#include "socc/tools/scan_log_writer.hpp"

namespace socc::tools {

/// Every sweep of stream into the log at out (overwritten); a partially written log is removed
/// on error. Event time = the sweep's end (when a live driver would publish it).
ScanLogSummary writeRecordingLog(sensors::ScanStream& stream, const std::filesystem::path& out,
                                 const std::string& robot_id, bool progress);

}  // namespace socc::tools
