#include "socc/odom/file_name_stamps.hpp"

#include <cctype>
#include <cmath>
#include <string>

namespace socc::odom {
namespace {

// Stamps before this (2001-09-09 in seconds) are taken for frame numbers or counters.
constexpr double kEpochSeconds = 1e9;

bool digitsOnly(const std::string& s) {
  if (s.empty()) return false;
  for (const char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

}  // namespace

std::optional<std::int64_t> fileNameStamp(const std::filesystem::path& name) {
  const std::string stem = name.stem().string();
  const std::size_t dot = stem.find('.');
  const std::string whole = stem.substr(0, dot);
  if (!digitsOnly(whole) || whole.size() > 19) return std::nullopt;
  if (dot != std::string::npos) {  // seconds with a fraction
    const std::string fraction = stem.substr(dot + 1);
    if (!digitsOnly(fraction) || whole.size() > 12) return std::nullopt;
    const double seconds = std::stod(whole + "." + fraction);
    if (seconds < kEpochSeconds) return std::nullopt;
    return std::llround(seconds * 1e6);
  }
  // An integer: its number of digits tells the unit (10: s, 13: ms, 16: us, 19: ns).
  const double value = std::stod(whole);
  for (const double per_second : {1.0, 1e3, 1e6, 1e9})
    if (value >= kEpochSeconds * per_second && value < 10.0 * kEpochSeconds * per_second)
      return std::llround(value / per_second * 1e6);
  return std::nullopt;
}

std::vector<std::int64_t> fileNameStamps(const std::vector<std::filesystem::path>& files) {
  std::vector<std::int64_t> stamps;
  for (const std::filesystem::path& f : files) {
    const std::optional<std::int64_t> t = fileNameStamp(f.filename());
    if (!t || (!stamps.empty() && *t <= stamps.back())) return {};
    stamps.push_back(*t);
  }
  return stamps;
}

}  // namespace socc::odom
