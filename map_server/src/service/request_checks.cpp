#include "request_checks.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "socc/pose_conversion.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::service {
namespace {

bool finite3(const double v[3]) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

Status checkBox(const double box_min[3], const double box_max[3], const ServiceLimits& limits) {
  if (!finite3(box_min) || !finite3(box_max)) return Status::invalid("box corners must be finite");
  for (int i = 0; i < 3; ++i) {
    if (box_min[i] > box_max[i]) return Status::invalid("box_min must be <= box_max");
    if (box_max[i] - box_min[i] > limits.max_region_extent)
      return Status::exhausted("region edge " + std::to_string(box_max[i] - box_min[i]) +
                               " m exceeds the server limit of " +
                               std::to_string(limits.max_region_extent) + " m");
  }
  return {};
}

// docs/lcm.md "Gravity reference": sigma 0 is none; a stated reference must be a unit vector.
Status checkGravity(const integrate_request_t& request) {
  const float sigma = request.gravity_sigma;
  if (!(std::isfinite(sigma) && sigma >= 0.f && sigma <= kMaxGravitySigma))
    return Status::invalid("gravity_sigma must be finite and in [0, " +
                           std::to_string(kMaxGravitySigma) + "] rad (0: no gravity reference)");
  if (sigma == 0.f) return {};
  const float* up = request.gravity_up;
  if (!(std::isfinite(up[0]) && std::isfinite(up[1]) && std::isfinite(up[2])))
    return Status::invalid("gravity_up must be finite when gravity_sigma > 0");
  const double norm =
      std::sqrt(double{up[0]} * up[0] + double{up[1]} * up[1] + double{up[2]} * up[2]);
  if (std::abs(norm - 1.0) > kGravityUpTolerance) {
    char text[128];
    std::snprintf(text, sizeof(text),
                  "gravity_up must be a unit vector (length %.4f, allowed 1 +- %.2f) when "
                  "gravity_sigma > 0",
                  norm, kGravityUpTolerance);
    return Status::invalid(text);
  }
  return {};
}

Status checkThreshold(float threshold) {
  if (!(threshold >= 0.0f && threshold <= 1.0f))
    return Status::invalid("occupancy_threshold must be in [0, 1]");
  return {};
}

}  // namespace

Status checkIntegrateRequest(const integrate_request_t& request, const map::MapConfig& config) {
  if (request.seq < 0) return Status::invalid("seq must be >= 0");
  // Always true after decode(); a request built in-process (tests, fuzzing) may lie, and
  // toCloud() and the journal's encode() rely on it.
  if (std::string why = wire::checkArrays(request.header); !why.empty())
    return Status::invalid(why);
  if (std::string why = wire::checkArrays(request); !why.empty()) return Status::invalid(why);
  if (static_cast<std::size_t>(request.num_points) > config.max_points_per_scan)
    return Status::exhausted("scan has " + std::to_string(request.num_points) +
                             " points; the server accepts at most " +
                             std::to_string(config.max_points_per_scan));
  if (request.num_labels != 0 && request.num_labels != request.num_points)
    return Status::invalid("num_labels must be 0 or num_points");
  if (request.num_times != 0 && request.num_times != request.num_points)
    return Status::invalid("num_times must be 0 or num_points");
  if (request.num_points > 0 &&
      !(std::isfinite(request.xyz_resolution) && request.xyz_resolution > 0.f))
    return Status::invalid("xyz_resolution must be finite and > 0");
  if (const std::string why = checkPose(request.sensor_pose, config.max_abs_coordinate);
      !why.empty())
    return Status::invalid("sensor_pose: " + why);
  return checkGravity(request);
}

Status checkChunkRequest(const chunk_request_t& request, const ServiceLimits& limits) {
  constexpr std::int32_t kKnownFields =
      chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS | chunk_request_t::FIELD_FREE |
      chunk_request_t::FIELD_INDEX | chunk_request_t::FIELD_MOMENTS;
  if ((request.fields & ~kKnownFields) != 0) return Status::invalid("unknown bits in fields");
  if (request.limit < 0) return Status::invalid("limit must be >= 0");
  if (Status s = checkThreshold(request.occupancy_threshold); !s.ok()) return s;
  if (request.shape == chunk_request_t::SHAPE_BOX)
    return checkBox(request.box_min, request.box_max, limits);
  if (request.shape != chunk_request_t::SHAPE_SPHERE)
    return Status::invalid("shape must be SHAPE_BOX or SHAPE_SPHERE");
  if (!finite3(request.center) || !std::isfinite(request.radius) || request.radius < 0.0)
    return Status::invalid("sphere centre must be finite and radius >= 0");
  if (2.0 * request.radius > limits.max_region_extent)
    return Status::exhausted("sphere diameter exceeds the server limit of " +
                             std::to_string(limits.max_region_extent) + " m");
  if (request.since_epoch != 0 &&
      (!finite3(request.since_center) || !std::isfinite(request.since_radius) ||
       request.since_radius < 0.0 || request.since_version < 0))
    return Status::invalid(
        "delta: since_center must be finite, since_radius and since_version >= 0");
  return {};
}

Status checkRenderRequest(const render_request_t& request, double voxel_size,
                          const ServiceLimits& limits) {
  if (Status s = checkBox(request.box_min, request.box_max, limits); !s.ok()) return s;
  if (Status s = checkThreshold(request.occupancy_threshold); !s.ok()) return s;
  if (request.mode < render_request_t::MODE_CLASS || request.mode > render_request_t::MODE_HEIGHT)
    return Status::invalid("unknown render mode");
  if (!std::isfinite(request.pixel_size) || request.pixel_size < 0.0)
    return Status::invalid("pixel_size must be finite and >= 0");
  const double pixel = request.pixel_size > 0.0 ? request.pixel_size : voxel_size;
  const double pixels = std::ceil((request.box_max[0] - request.box_min[0]) / pixel) *
                        std::ceil((request.box_max[1] - request.box_min[1]) / pixel);
  // !(pixels <= limit) also catches NaN/inf; the message formats the double because a cast of a
  // huge value to an integer type would be undefined behaviour.
  if (!(pixels <= static_cast<double>(limits.max_render_pixels))) {
    char count[32];
    std::snprintf(count, sizeof(count), "%.3g", pixels);
    return Status::exhausted(std::string("image would have ") + count +
                             " pixels; the server limit is " +
                             std::to_string(limits.max_render_pixels));
  }
  if (pixels < 1.0) return Status::invalid("render box is empty");
  return {};
}

Status checkRobotStatusRequest(const robot_status_request_t& request) {
  if (request.seq < 0) return Status::invalid("seq must be >= 0");
  if (request.tracking_state < robot_status_request_t::TRACKING ||
      request.tracking_state > robot_status_request_t::RELOCALIZING)
    return Status::invalid("unknown tracking_state " + std::to_string(request.tracking_state));
  // The reason is shown in every map_stats_t and in terminals (socc-cli stats).
  constexpr std::size_t kMaxReason = 200;
  if (request.reason.size() > kMaxReason)
    return Status::invalid("reason is longer than " + std::to_string(kMaxReason) + " bytes");
  for (const char c : request.reason)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return Status::invalid("reason contains control characters");
  return {};
}

Status checkLocalizeRequest(const localize_request_t& request, const map::MapConfig& config,
                            const ServiceLimits& limits) {
  if (request.num_points < 1) return Status::invalid("num_points must be >= 1");
  if (request.num_points > limits.max_localize_points)
    return Status::exhausted("num_points " + std::to_string(request.num_points) +
                             " exceeds the server limit of " +
                             std::to_string(limits.max_localize_points) + " (downsample the scan)");
  for (const auto& row : request.xyz)
    for (const float v : row)
      if (!(std::abs(v) <= config.max_abs_coordinate))
        return Status::invalid("points must be finite and within max_abs_coordinate");
  if (!finite3(request.hint_position) || !std::isfinite(request.hint_yaw) ||
      !std::isfinite(request.hint_radius) || !(request.hint_yaw_tolerance >= 0.0))
    return Status::invalid("hint values must be finite (yaw tolerance >= 0)");
  constexpr std::int32_t kMaxCandidates = 16;
  if (request.max_candidates < 1 || request.max_candidates > kMaxCandidates)
    return Status::invalid("max_candidates must be in 1.." + std::to_string(kMaxCandidates));
  if (request.num_check < 0 || request.num_check > kMaxCandidates)
    return Status::invalid("num_check must be in 0.." + std::to_string(kMaxCandidates));
  for (const pose3d_t& pose : request.check_pose)
    if (const std::string why = checkPose(pose, config.max_abs_coordinate); !why.empty())
      return Status::invalid("check_pose: " + why);
  return {};
}

Status resolveCommandPath(const std::string& path, const std::filesystem::path& file_dir,
                          std::filesystem::path& resolved) {
  if (path.empty()) return Status::invalid("path is empty");
  const std::filesystem::path given(path);
  for (const auto& part : given)
    if (part == "..") return Status::invalid("path may not contain '..'");
  const std::filesystem::path root = std::filesystem::absolute(file_dir).lexically_normal();
  const std::filesystem::path full =
      (given.is_absolute() ? given : root / given).lexically_normal();
  const auto rel = full.lexically_relative(root);
  if (rel.empty() || rel == "." || *rel.begin() == "..")
    return Status::invalid("path must be inside the server's file directory " + root.string());
  resolved = full;
  return {};
}

}  // namespace socc::service
