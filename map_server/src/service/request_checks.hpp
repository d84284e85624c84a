#pragma once
// Validation of decoded requests, before they touch the map. Each returns an OK Status or
// the reason (INVALID_ARGUMENT for malformed values, RESOURCE_EXHAUSTED for too-large asks).
#include <filesystem>

#include "service_config.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/localize_request_t.hpp"
#include "socc/render_request_t.hpp"
#include "socc/robot_status_request_t.hpp"
#include "status.hpp"

namespace socc::service {

/// A stated gravity reference (docs/lcm.md "Gravity reference"): its sigma at most this [rad]
/// (29 deg: anything looser says nothing), its up vector this close to unit length.
inline constexpr float kMaxGravitySigma = 0.5f;
inline constexpr double kGravityUpTolerance = 0.01;

/// The wire form of an Integrate: seq, array sizes, point count limit, the pose's encoding, the
/// gravity reference (finite sigma in [0, kMaxGravitySigma]; when > 0 a finite unit gravity_up).
/// The content (points, labels, pose as a rotation) is checked once by the map's validate().
Status checkIntegrateRequest(const integrate_request_t& request, const map::MapConfig& config);
Status checkChunkRequest(const chunk_request_t& request, const ServiceLimits& limits);
/// Known tracking state, seq >= 0, a short printable reason.
Status checkRobotStatusRequest(const robot_status_request_t& request);
Status checkRenderRequest(const render_request_t& request, double voxel_size,
                          const ServiceLimits& limits);
/// 1..max_localize_points finite points within the map bounds, a finite hint, 1..16 candidates.
Status checkLocalizeRequest(const localize_request_t& request, const map::MapConfig& config,
                            const ServiceLimits& limits);

/// Resolves a client-given path inside file_dir; refuses empty, absolute-outside and ".." paths.
Status resolveCommandPath(const std::string& path, const std::filesystem::path& file_dir,
                          std::filesystem::path& resolved);

}  // namespace socc::service
