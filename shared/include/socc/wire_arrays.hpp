#pragma once
// The structure-of-arrays fields of socc messages (docs/lcm.md, "Array layout"): a field
// `T a[R][n]` is R rows of n values, e.g. xyz[0] = x of every point, so lcm-gen encodes and
// decodes each row in one bulk call. decode() always yields R rows (empty when n == 0), but
// encode() trusts the counts and reads R rows of n values from the vectors: a hand-built
// message must pass checkArrays() before it is encoded.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/localize_request_t.hpp"
#include "socc/point_cloud.hpp"
#include "socc/rounding.hpp"
#include "socc/scan_t.hpp"

namespace socc::wire {

template <typename T>
using Rows = std::vector<std::vector<T>>;

/// True when a is `rows` rows of exactly `count` values, or empty when count == 0 (nothing is
/// encoded then, so a default-constructed message is fine).
template <typename T>
bool hasRows(const Rows<T>& a, std::int64_t rows, std::int64_t count) {
  if (count == 0 && a.empty()) return true;
  if (count < 0 || rows < 0 || a.size() != static_cast<std::size_t>(rows)) return false;
  for (const auto& row : a)
    if (row.size() != static_cast<std::size_t>(count)) return false;
  return true;
}

/// True when a has exactly count values (count < 0 never matches).
template <typename T>
bool hasCount(const std::vector<T>& a, std::int64_t count) {
  return count >= 0 && a.size() == static_cast<std::size_t>(count);
}

/// Quantizes points for integrate_request_t (docs/lcm.md "Point quantization"): returns the
/// resolution [m per unit], the finest that holds the largest |coordinate| in an int16.
/// Throws std::invalid_argument for a non-finite point.
inline float quantizePoints(const Points& points, Rows<std::int16_t>& xyz) {
  float largest = 0.f;
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) throw std::invalid_argument("non-finite point: cannot be sent");
    largest = std::max(largest, p.cwiseAbs().maxCoeff());
  }
  // 32766, not 32767: float rounding must not carry the largest coordinate past the int16 range.
  const float resolution = std::max(largest / 32766.f, 1e-6f);
  const float inv = 1.f / resolution;
  const std::size_t n = points.size();
  xyz.resize(3);
  for (auto& row : xyz) row.resize(n);
  for (int a = 0; a < 3; ++a) {
    std::int16_t* row = xyz[a].data();
    for (std::size_t i = 0; i < n; ++i)
      row[i] = static_cast<std::int16_t>(roundHalfAway(points[i][a] * inv));
  }
  return resolution;
}

/// The points of quantized rows (3 rows of equal length); throws std::invalid_argument when
/// the rows are not that, or when there are points and the resolution is not finite and > 0.
inline Points pointsFromQuantized(const Rows<std::int16_t>& xyz, float resolution) {
  Points points;
  if (xyz.empty()) return points;
  const std::size_t n = xyz.size() == 3 ? xyz[0].size() : 0;
  if (xyz.size() != 3 || xyz[1].size() != n || xyz[2].size() != n)
    throw std::invalid_argument("xyz must be 3 rows of equal length");
  if (n == 0) return points;  // no point: the resolution says nothing
  if (!(std::isfinite(resolution) && resolution > 0.f))
    throw std::invalid_argument("xyz_resolution must be finite and > 0");
  points.resize(n);
  const std::int16_t* x = xyz[0].data();
  const std::int16_t* y = xyz[1].data();
  const std::int16_t* z = xyz[2].data();
  for (std::size_t i = 0; i < n; ++i) points[i] = Eigen::Vector3f(x[i], y[i], z[i]) * resolution;
  return points;
}

/// Value i of every row (e.g. the 3 coordinates of point i). Allocates: for tests and
/// diagnostics, not for per-point loops.
template <typename T>
std::vector<T> column(const Rows<T>& a, std::size_t i) {
  std::vector<T> values;
  values.reserve(a.size());
  for (const auto& row : a) values.push_back(row.at(i));
  return values;
}

/// xyz = points by axis (3 rows, each sized once).
inline void pointsToRows(const Points& points, Rows<float>& xyz) {
  const std::size_t n = points.size();
  xyz.resize(3);
  for (auto& row : xyz) row.resize(n);
  float* x = xyz[0].data();
  float* y = xyz[1].data();
  float* z = xyz[2].data();
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = points[i].x();
    y[i] = points[i].y();
    z[i] = points[i].z();
  }
}

/// The points of xyz (3 rows of equal length, or empty). Throws std::invalid_argument otherwise.
inline Points pointsFromRows(const Rows<float>& xyz) {
  Points points;
  if (xyz.empty()) return points;
  const std::size_t n = xyz.size() == 3 ? xyz[0].size() : 0;
  if (xyz.size() != 3 || xyz[1].size() != n || xyz[2].size() != n)
    throw std::invalid_argument("xyz must be 3 rows of equal length");
  points.resize(n);
  const float* x = xyz[0].data();
  const float* y = xyz[1].data();
  const float* z = xyz[2].data();
  for (std::size_t i = 0; i < n; ++i) points[i] = Eigen::Vector3f(x[i], y[i], z[i]);
  return points;
}

// checkArrays: empty when every array of the message matches its count field (what encode()
// relies on), otherwise which one does not. Decoded messages always pass. A request's header
// is checked on its own: MapClient replaces the mac before encoding anyway.

inline std::string checkArrays(const request_header_t& h) {
  if (!hasCount(h.mac, h.mac_len)) return "header.mac_len does not match the mac array";
  return {};
}

inline std::string checkArrays(const integrate_request_t& m) {
  if (!hasRows(m.xyz, 3, m.num_points))
    return "num_points does not match the point array (xyz must be 3 rows of num_points)";
  if (!hasCount(m.label, m.num_labels)) return "num_labels does not match the label array";
  if (!hasCount(m.time, m.num_times)) return "num_times does not match the time array";
  return {};
}

inline std::string checkArrays(const localize_request_t& m) {
  if (!hasRows(m.xyz, 3, m.num_points))
    return "num_points does not match the point array (xyz must be 3 rows of num_points)";
  if (!hasCount(m.check_pose, m.num_check)) return "num_check does not match check_pose";
  return {};
}

inline std::string checkArrays(const scan_t& m) {
  if (!hasRows(m.xyz, 3, m.num_points))
    return "num_points does not match xyz (3 rows of num_points)";
  if (!hasCount(m.intensity, m.num_intensities))
    return "num_intensities does not match the intensity array";
  if (!hasCount(m.label, m.num_labels)) return "num_labels does not match the label array";
  if (!hasCount(m.time, m.num_times)) return "num_times does not match the time array";
  return {};
}

inline std::string checkArrays(const chunk_reply_t& m) {
  if (!hasRows(m.block, 3, m.n_blocks) || !hasCount(m.block_voxels, m.n_blocks))
    return "n_blocks does not match block or block_voxels";
  if (!hasRows(m.index, 3, m.n_index)) return "n_index does not match index";
  const std::int32_t f = m.n_features;
  if (!hasRows(m.first_point, 3, f) || !hasRows(m.normal, 2, f) || !hasCount(m.planarity, f) ||
      !hasCount(m.occupancy, f) || !hasCount(m.label, f) || !hasCount(m.label_prob, f))
    return "n_features does not match the feature arrays";
  const std::int32_t s = m.n_stats;
  if (m.num_classes < 0) return "negative num_classes";
  if (!hasRows(m.mean, 3, s) || !hasRows(m.covariance, 6, s) || !hasCount(m.count, s) ||
      !hasCount(m.log_odds, s) || !hasRows(m.class_prob, m.num_classes, s))
    return "n_stats or num_classes does not match the statistics arrays";
  if (!hasCount(m.point_count, m.n_counts)) return "n_counts does not match point_count";
  if (!hasRows(m.moment_mean, 3, m.n_moments) || !hasRows(m.moment_m2, 6, m.n_moments))
    return "n_moments does not match the moment arrays";
  if (!hasRows(m.free_index, 3, m.n_free)) return "n_free does not match free_index";
  return {};
}

}  // namespace socc::wire
