#include "hesai_calibration.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace socc::sensors {
namespace {

// "1,14.97,0.08" -> three numbers; false when the line is not three comma-separated numbers.
bool parseHesaiCalibrationRow(const std::string& line, double& id, double& elevation,
                              double& azimuth) {
  std::istringstream in(line);
  char c1 = 0, c2 = 0;
  if (!(in >> id >> c1 >> elevation >> c2 >> azimuth) || c1 != ',' || c2 != ',') return false;
  std::string rest;
  in >> rest;
  return rest.empty() || rest[0] == ',';  // extra columns of newer exports are ignored
}

}  // namespace

HesaiCalibration readHesaiCalibration(const std::filesystem::path& file, int lasers) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the angle-correction file");
  const auto fail = [&](int line, const std::string& what) {
    return std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + what);
  };
  HesaiCalibration cal;
  cal.elevation_deg.assign(static_cast<std::size_t>(lasers), NAN);
  cal.azimuth_offset_deg.assign(static_cast<std::size_t>(lasers), NAN);
  std::string line;
  int number = 0, rows = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    double id = 0, elevation = 0, azimuth = 0;
    if (!parseHesaiCalibrationRow(line, id, elevation, azimuth)) {
      if (rows == 0 && number == 1) continue;  // the header line
      throw fail(number, "expected \"channel,elevation,azimuth\", got \"" + line + "\"");
    }
    const bool in_range = id >= 1 && id <= lasers;  // before converting: any double may come
    const int channel = in_range ? static_cast<int>(id) : 0;
    if (!in_range || channel != id)
      throw fail(number, "channel " + line.substr(0, line.find(',')) + " is not in 1.." +
                             std::to_string(lasers) + " (a calibration of another model?)");
    if (!std::isfinite(elevation) || !std::isfinite(azimuth) || std::abs(elevation) > 90.0 ||
        std::abs(azimuth) > 45.0)
      throw fail(number, "implausible angles (elevation " + std::to_string(elevation) +
                             ", azimuth " + std::to_string(azimuth) + " deg)");
    const auto i = static_cast<std::size_t>(channel - 1);
    if (!std::isnan(cal.elevation_deg[i]))
      throw fail(number, "channel " + std::to_string(channel) + " appears twice");
    cal.elevation_deg[i] = static_cast<float>(elevation);
    cal.azimuth_offset_deg[i] = static_cast<float>(azimuth);
    ++rows;
  }
  if (rows != lasers)
    throw std::runtime_error(file.string() + ": " + std::to_string(rows) +
                             " channels, the sensor has " + std::to_string(lasers) +
                             " (a calibration of another model?)");
  return cal;
}

}  // namespace socc::sensors
