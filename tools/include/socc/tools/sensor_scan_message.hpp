#pragma once
// A decoded sweep (socc_sensors) as the scan_t that socc-lidar publishes and socc-to-lcmlog
// logs: utime in whole microseconds of the recording's clock, per-point times relative to it
// (the sub-microsecond remainder moved into them), intensities, no labels.
#include <string>

#include "socc/scan_t.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::tools {

scan_t toScanMessage(const sensors::SensorScan& sweep, const std::string& robot_id);

/// Where a sweep ends [us, the recording's clock]: its last point's time (published then).
std::int64_t sweepEndUtime(const sensors::SensorScan& sweep);

}  // namespace socc::tools
