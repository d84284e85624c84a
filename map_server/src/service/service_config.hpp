#pragma once
// Settings of the map service: the grid parameters plus the limits that protect the server
// from oversized requests (YAML: map_server/config/server.yaml).
#include <cstdint>
#include <filesystem>

#include "consistency_params.hpp"
#include "global_localizer.hpp"
#include "socc/map/map_config.hpp"

namespace socc::service {

struct ServiceLimits {
  std::int64_t max_chunk_voxels = 2'000'000;  // per GET_CHUNK reply; more -> truncated
  double max_region_extent = 2000.0;          // [m] box edge / sphere diameter; more -> rejected
  std::int64_t max_reply_bytes = 60'000'000;  // encoded reply; more -> RESOURCE_EXHAUSTED
  std::int64_t max_render_pixels = 16'000'000;
  std::int64_t max_robots = 1024;              // robot states kept; new robots beyond -> rejected
  std::int32_t max_localize_points = 100'000;  // per LOCALIZE scan
  // LOCALIZE searches waiting behind the one running (its own thread); more -> RESOURCE_EXHAUSTED.
  std::int32_t max_waiting_searches = 2;
  // Fairness: requests per second one robot (client id) may make, with a burst of one second's
  // worth; more -> RESOURCE_EXHAUSTED (robot_rate_limiter.hpp). 0 = no limit.
  double robot_integrate_rate = 40.0;
  double robot_chunk_rate = 40.0;
};

// How far a robot may move between two of its INTEGRATEs (plausibility.hpp): speed times the
// scan-time difference plus a slack for timestamp jitter and pose noise. The defaults leave
// a car at 20 m/s or a handheld sensor turning 180 deg/s a factor of 2 (KITTI: <= 25 m/s).
struct PlausibilityLimits {
  bool enabled = true;
  double max_linear_speed = 40.0;    // [m/s]
  double max_angular_speed = 360.0;  // [deg/s]
  double linear_slack = 0.5;         // [m]
  double angular_slack = 10.0;       // [deg]
};

struct ServerConfig {
  map::MapConfig map;
  ServiceLimits limits;
  PlausibilityLimits plausibility;
  localization::LocalizerParams localization;  // LOCALIZE search (docs/relocalization.md)
  // Loop closure and robot-to-robot alignment (docs/consistency.md); off by default.
  consistency::ConsistencyParams consistency;
  // MAP_COMMAND paths (save/load/export) are resolved inside this directory, so a client
  // cannot make the server read or write arbitrary files.
  std::filesystem::path file_dir = ".";
  // Shared key (docs/security.md); empty = requests are not authenticated.
  std::filesystem::path key_file;
  bool auth_queries = false;  // also require a MAC on read-only queries
};

/// Loads server.yaml: optional `map_config` and `key_file` (relative to this file), `file_dir`,
/// `auth_queries`, `limits:`, `plausibility:` and `consistency:` keys. Unknown keys, bad or
/// out-of-range values throw std::runtime_error naming the file and the key (socc/yaml_fields.hpp).
ServerConfig loadServerConfig(const std::filesystem::path& file);

}  // namespace socc::service
