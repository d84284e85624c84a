#include "bags/pointcloud2_scan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace socc::sensors::bags {

namespace {

constexpr std::uint8_t kFloat32 = 7;
constexpr std::uint8_t kFloat64 = 8;
constexpr double kSecondsToNs = 1e9;
// A sweep's points lie within this of each other and (relative times) of the header stamp.
constexpr double kMaxSweepSeconds = 2.0;
// Floating-point times at or above this are absolute seconds (after 1973), below relative.
constexpr double kAbsoluteSecondsMin = 1e8;

std::size_t pointFieldBytes(std::uint8_t datatype) {
  constexpr std::array<std::size_t, 9> bytes = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return datatype < bytes.size() ? bytes[datatype] : 0;
}

bool isIntegerField(std::uint8_t datatype) {
  return datatype >= 1 && datatype <= 6;
}

/// One field of the point layout, read as a double (exact for every PointField datatype but
/// float64 itself).
struct FieldAccess {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  bool big_endian = false;

  double value(const std::uint8_t* point) const {
    const std::uint8_t* p = point + offset;
    switch (datatype) {
      case 1:
        return loadValue<std::int8_t>(p, big_endian);
      case 2:
        return loadValue<std::uint8_t>(p, big_endian);
      case 3:
        return loadValue<std::int16_t>(p, big_endian);
      case 4:
        return loadValue<std::uint16_t>(p, big_endian);
      case 5:
        return loadValue<std::int32_t>(p, big_endian);
      case 6:
        return loadValue<std::uint32_t>(p, big_endian);
      case 7:
        return loadValue<float>(p, big_endian);
      default:
        return loadValue<double>(p, big_endian);
    }
  }
};

/// The first field named one of names (case-insensitive), checked to lie inside point_step.
std::optional<FieldAccess> findField(const PointCloud2Msg& cloud,
                                     std::initializer_list<const char*> names) {
  const auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  for (const char* name : names) {
    for (const PointFieldMsg& f : cloud.fields) {
      if (lower(f.name) != name) continue;
      const std::size_t bytes = pointFieldBytes(f.datatype);
      if (bytes == 0) {
        throw FormatError("field " + f.name + " has datatype " + std::to_string(f.datatype));
      }
      if (std::uint64_t{f.offset} + bytes > cloud.point_step) {
        throw FormatError("field " + f.name + " ends past point_step " +
                          std::to_string(cloud.point_step));
      }
      return FieldAccess{f.name, f.offset, f.datatype, cloud.is_bigendian};
    }
  }
  return std::nullopt;
}

FieldAccess coordinateField(const PointCloud2Msg& cloud, const char* name) {
  const auto f = findField(cloud, {name});
  if (!f) throw FormatError(std::string("no field ") + name);
  if (f->datatype != kFloat32 && f->datatype != kFloat64) {
    throw FormatError(std::string("field ") + name + " is not float32 or float64");
  }
  return *f;
}

void checkRows(const PointCloud2Msg& cloud) {
  if (cloud.height == 0 || cloud.width == 0) return;
  if (cloud.point_step == 0) throw FormatError("point_step 0");
  const std::uint64_t row_bytes = std::uint64_t{cloud.width} * cloud.point_step;
  if (cloud.height > 1 && cloud.row_step < row_bytes) {
    throw FormatError("row_step " + std::to_string(cloud.row_step) + " < width * point_step");
  }
  const std::uint64_t needed = std::uint64_t{cloud.height - 1} * cloud.row_step + row_bytes;
  if (needed > cloud.data.size) {
    throw FormatError(std::to_string(cloud.height) + " x " + std::to_string(cloud.width) +
                      " points need " + std::to_string(needed) + " bytes, data has " +
                      std::to_string(cloud.data.size));
  }
}

/// How raw time values become absolute times [ns] (docs/sensors_bags.md, "Point times").
struct TimeRule {
  bool absolute = false;
  double to_ns = 1.0;  // raw unit -> ns
  std::string problem;
};

/// Floating point: seconds, absolute from 1e8 s on (float64 only: float32 cannot resolve a
/// sweep at epoch magnitudes), else relative to the header stamp. Integer (at most 32 bits, so
/// never absolute): relative to the header stamp in ns, or in us when the span is 1e3..1e6
/// (1 ms..1 s in us but 1 us..1 ms in ns, shorter than any sweep).
TimeRule timeRule(const FieldAccess& field, double min_raw, double max_raw) {
  TimeRule rule;
  if (!isIntegerField(field.datatype)) {
    rule.to_ns = kSecondsToNs;
    rule.absolute = min_raw >= kAbsoluteSecondsMin;
    if (rule.absolute && field.datatype == kFloat32) {
      rule.problem = "float32 absolute seconds are too coarse for point times";
    }
    return rule;
  }
  const double span = max_raw - min_raw;
  rule.to_ns = span >= 1e3 && span < 1e6 ? 1e3 : 1.0;
  return rule;
}

std::int64_t absoluteNs(double raw, const TimeRule& rule, std::int64_t header_ns) {
  if (!rule.absolute) return header_ns + std::llround(raw * rule.to_ns);
  const double whole = std::floor(raw);  // seconds apart from their fraction keep ns precision
  return static_cast<std::int64_t>(whole) * 1'000'000'000 +
         std::llround((raw - whole) * rule.to_ns);
}

/// Fills scan.stamp_ns and scan.time from the raw time values of the kept points, or returns
/// why they cannot be used (scan.stamp_ns is then the header's).
std::string applyTimes(const FieldAccess& field, const std::vector<double>& raw,
                       std::int64_t header_ns, SensorScan& scan) {
  if (raw.empty()) return {};
  const auto [lo, hi] = std::minmax_element(raw.begin(), raw.end());
  const TimeRule rule = timeRule(field, *lo, *hi);
  if (!rule.problem.empty()) return rule.problem;
  const double span_s = (*hi - *lo) * rule.to_ns / kSecondsToNs;
  if (span_s > kMaxSweepSeconds) {
    return "the times span " + std::to_string(span_s) + " s, more than one sweep";
  }
  if (!rule.absolute) {
    const double offset_s = std::max(std::abs(*lo), std::abs(*hi)) * rule.to_ns / kSecondsToNs;
    if (offset_s > kMaxSweepSeconds) {
      return "relative times up to " + std::to_string(offset_s) + " s from the header stamp";
    }
  }
  const std::int64_t stamp = absoluteNs(*lo, rule, header_ns);
  scan.stamp_ns = stamp;
  scan.time.resize(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    scan.time[i] = static_cast<float>(
        static_cast<double>(absoluteNs(raw[i], rule, header_ns) - stamp) / kSecondsToNs);
  }
  return {};
}

struct CloudFields {
  FieldAccess x, y, z;
  std::optional<FieldAccess> intensity, ring, time;
};

CloudFields cloudFields(const PointCloud2Msg& cloud) {
  CloudFields f{coordinateField(cloud, "x"),
                coordinateField(cloud, "y"),
                coordinateField(cloud, "z"),
                findField(cloud, {"intensity", "reflectivity"}),
                findField(cloud, {"ring", "channel"}),
                findField(cloud, {"t", "time", "offset_time", "time_stamp", "timestamp"})};
  if (f.ring && !isIntegerField(f.ring->datatype)) {
    throw FormatError("field " + f.ring->name + " is not an integer");
  }
  return f;
}

}  // namespace

PointCloud2Conversion convertPointCloud2(const PointCloud2Msg& cloud,
                                         std::int64_t receive_stamp_ns) {
  checkRows(cloud);
  const CloudFields fields = cloudFields(cloud);
  PointCloud2Conversion out;
  SensorScan& scan = out.scan;
  const std::int64_t header_ns =
      cloud.header.stamp_ns != 0 ? cloud.header.stamp_ns : receive_stamp_ns;
  scan.stamp_ns = header_ns;
  scan.frame_id = cloud.header.frame_id;
  const std::size_t n = std::size_t{cloud.height} * cloud.width;
  if (n == 0) return out;  // also no loop over 2^32 empty rows
  scan.points.reserve(n);
  std::vector<double> raw_times;
  for (std::uint32_t row = 0; row < cloud.height; ++row) {
    const std::uint8_t* row_data = cloud.data.data + std::size_t{row} * cloud.row_step;
    for (std::uint32_t col = 0; col < cloud.width; ++col) {
      const std::uint8_t* p = row_data + std::size_t{col} * cloud.point_step;
      const Eigen::Vector3f xyz(static_cast<float>(fields.x.value(p)),
                                static_cast<float>(fields.y.value(p)),
                                static_cast<float>(fields.z.value(p)));
      const double t = fields.time ? fields.time->value(p) : 0.0;
      if (!xyz.allFinite() || xyz.isZero() || !std::isfinite(t)) {
        ++out.dropped_points;
        continue;
      }
      scan.points.push_back(xyz);
      if (fields.intensity)
        scan.intensity.push_back(static_cast<float>(fields.intensity->value(p)));
      if (fields.ring) {
        const double ring = fields.ring->value(p);
        if (ring < 0 || ring > std::numeric_limits<std::uint16_t>::max()) {
          throw FormatError("ring " + std::to_string(ring) + " out of range");
        }
        scan.ring.push_back(static_cast<std::uint16_t>(ring));
      }
      if (fields.time) raw_times.push_back(t);
    }
  }
  if (fields.time) {
    out.time_problem = applyTimes(*fields.time, raw_times, header_ns, scan);
    if (out.time_problem.empty()) {
      out.time_field = fields.time->name;
    } else {
      out.time_problem = "time field " + fields.time->name + ": " + out.time_problem;
    }
  }
  return out;
}

}  // namespace socc::sensors::bags
