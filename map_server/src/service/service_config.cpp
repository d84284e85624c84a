#include "service_config.hpp"

#include <optional>
#include <string>
#include <utility>

#include "socc/yaml_fields.hpp"

namespace socc::service {
namespace {

// The ranges of limits: and plausibility: (the map grid validates its own file).
std::string validate(const ServerConfig& c) {
  const ServiceLimits& l = c.limits;
  const PlausibilityLimits& p = c.plausibility;
  const std::pair<const char*, double> positive[] = {
      {"limits.max_chunk_voxels", static_cast<double>(l.max_chunk_voxels)},
      {"limits.max_region_extent", l.max_region_extent},
      {"limits.max_reply_bytes", static_cast<double>(l.max_reply_bytes)},
      {"limits.max_render_pixels", static_cast<double>(l.max_render_pixels)},
      {"limits.max_robots", static_cast<double>(l.max_robots)},
      {"limits.max_localize_points", static_cast<double>(l.max_localize_points)},
      {"localization.max_draws", static_cast<double>(c.localization.search.max_iterations)},
      {"localization.max_inlier_tests",
       static_cast<double>(c.localization.search.max_inlier_tests)},
      {"localization.feature_candidates",
       static_cast<double>(c.localization.search.correspondence_randomness)},
      {"plausibility.max_linear_speed", p.max_linear_speed},
      {"plausibility.max_angular_speed", p.max_angular_speed},
  };
  for (const auto& [key, value] : positive)
    if (!(value > 0.0)) return std::string(key) + " must be > 0";  // NaN too
  // 0: no per-robot limit (RobotRateLimiter), as server.yaml documents.
  if (!(l.robot_integrate_rate >= 0.0)) return "limits.robot_integrate_rate must be >= 0";
  if (!(l.robot_chunk_rate >= 0.0)) return "limits.robot_chunk_rate must be >= 0";
  if (l.max_waiting_searches < 0) return "limits.max_waiting_searches must be >= 0";
  if (!(p.linear_slack >= 0.0)) return "plausibility.linear_slack must be >= 0";
  if (!(p.angular_slack >= 0.0)) return "plausibility.angular_slack must be >= 0";
  const consistency::ConsistencyParams& k = c.consistency;
  if (!(k.keyframe_distance > 0.0)) return "consistency.keyframe_distance must be > 0";
  if (!(k.keyframe_voxel > 0.0)) return "consistency.keyframe_voxel must be > 0";
  if (!(k.min_loop_travel >= 0.0)) return "consistency.min_loop_travel must be >= 0";
  if (!(k.search_radius >= 0.0)) return "consistency.search_radius must be >= 0";
  if (k.max_pending_scans < 1) return "consistency.max_pending_scans must be >= 1";
  if (!(k.rebuild_voxel > 0.0)) return "consistency.rebuild_voxel must be > 0";
  if (!(k.rebuild_min_shift >= 0.0)) return "consistency.rebuild_min_shift must be >= 0";
  if (!(k.rebuild_region_shift >= 0.0)) return "consistency.rebuild_region_shift must be >= 0";
  if (!(k.rebuild_region_max_share >= 0.0 && k.rebuild_region_max_share <= 1.0))
    return "consistency.rebuild_region_max_share must be in [0, 1]";
  if (!(k.correction_window >= 0.0)) return "consistency.correction_window must be >= 0";
  if (!(k.rebuild_max_wait >= 0.0)) return "consistency.rebuild_max_wait must be >= 0";
  if (!(k.snap_min_t >= 0.0) || !(k.snap_min_r >= 0.0))
    return "consistency.snap_min_t and snap_min_r must be >= 0";
  if (!(k.gravity_sigma_floor > 0.0)) return "consistency.gravity_sigma_floor must be > 0";
  if (!(k.max_descriptor_distance >= 0.0 && k.max_descriptor_distance <= 1.0))
    return "consistency.max_descriptor_distance must be in [0, 1]";
  return {};
}

}  // namespace

ServerConfig loadServerConfig(const std::filesystem::path& file) {
  ServerConfig config;
  ServiceLimits& l = config.limits;
  const YamlFields limits = {
      {"max_chunk_voxels", &l.max_chunk_voxels},
      {"max_region_extent", &l.max_region_extent},
      {"max_reply_bytes", &l.max_reply_bytes},
      {"max_render_pixels", &l.max_render_pixels},
      {"max_robots", &l.max_robots},
      {"max_localize_points", &l.max_localize_points},
      {"max_waiting_searches", &l.max_waiting_searches},
      {"robot_integrate_rate", &l.robot_integrate_rate},
      {"robot_chunk_rate", &l.robot_chunk_rate},
  };
  PlausibilityLimits& p = config.plausibility;
  const YamlFields plausibility = {
      {"enabled", &p.enabled},
      {"max_linear_speed", &p.max_linear_speed},
      {"max_angular_speed", &p.max_angular_speed},
      {"linear_slack", &p.linear_slack},
      {"angular_slack", &p.angular_slack},
  };
  consistency::ConsistencyParams& k = config.consistency;
  const YamlFields consistency = {
      {"enabled", &k.enabled},
      {"keyframe_distance", &k.keyframe_distance},
      {"keyframe_voxel", &k.keyframe_voxel},
      {"min_loop_travel", &k.min_loop_travel},
      {"search_radius", &k.search_radius},
      {"drift_share", &k.drift_share},
      {"max_descriptor_distance", &k.max_descriptor_distance},
      {"max_pending_scans", &k.max_pending_scans},
      {"correct_grid", &k.correct_grid},
      {"rebuild_voxel", &k.rebuild_voxel},
      {"rebuild_min_shift", &k.rebuild_min_shift},
      {"rebuild_region", &k.rebuild_region},
      {"rebuild_region_shift", &k.rebuild_region_shift},
      {"rebuild_region_max_share", &k.rebuild_region_max_share},
      {"correction_window", &k.correction_window},
      {"rebuild_max_wait", &k.rebuild_max_wait},
      {"scan_to_scan_edges", &k.scan_to_scan_edges},
      {"snap_min_t", &k.snap_min_t},
      {"snap_min_r", &k.snap_min_r},
      {"gravity_priors", &k.gravity_priors},
      {"gravity_sigma_floor", &k.gravity_sigma_floor},
  };
  localization::SearchParams& search = config.localization.search;
  const YamlFields localization = {
      {"max_draws", &search.max_iterations},
      {"max_inlier_tests", &search.max_inlier_tests},
      {"feature_candidates", &search.correspondence_randomness},
  };
  // Paths are kept as given until the file is read, so relative ones resolve against it.
  std::optional<std::string> map_config, file_dir, key_file;
  loadYamlFields(file, "server config",
                 {{"map_config", &map_config},
                  {"file_dir", &file_dir},
                  {"key_file", &key_file},
                  {"auth_queries", &config.auth_queries},
                  {"limits", &limits},
                  {"plausibility", &plausibility},
                  {"consistency", &consistency},
                  {"localization", &localization}},
                 [&config] { return validate(config); });
  const auto beside = [&file](const std::filesystem::path& path) {
    return path.is_relative() ? file.parent_path() / path : path;
  };
  if (map_config) config.map = map::loadMapConfig(beside(*map_config));
  if (file_dir) config.file_dir = *file_dir;
  if (key_file) config.key_file = beside(*key_file);
  return config;
}

}  // namespace socc::service
