#include "socc/odom/odom_config.hpp"

#include <cmath>
#include <functional>

#include "socc/yaml_fields.hpp"

namespace socc::odom {
namespace {

// The YAML keys, named like the fields (config/default.yaml documents each).
YamlFields fields(OdomConfig& c) {
  return {
      {"min_range", &c.min_range},
      {"max_range", &c.max_range},
      {"deskew", &c.deskew},
      {"vertical_angle_correction_deg", &c.vertical_angle_correction_deg},
      {"frame_period", &c.frame_period},
      {"deskew_reference_time", &c.deskew_reference_time},
      {"deskew_iterations", &c.deskew_iterations},
      {"sweep_twist_sigma_linear", &c.sweep_twist_sigma_linear},
      {"sweep_twist_sigma_angular", &c.sweep_twist_sigma_angular},
      {"range_calibration", &c.range_calibration},
      {"azimuth_times", &c.azimuth_times},
      {"azimuth_start_deg", &c.azimuth_start_deg},
      {"azimuth_clockwise", &c.azimuth_clockwise},
      {"scan_time_in_sweep", &c.scan_time_in_sweep},
      {"min_inlier_fraction", &c.min_inlier_fraction},
      {"max_residual_ratio", &c.max_residual_ratio},
      {"min_constraint", &c.min_constraint},
      {"hold_degenerate_direction", &c.hold_degenerate_direction},
      {"max_linear_speed", &c.max_linear_speed},
      {"max_angular_speed", &c.max_angular_speed},
      {"max_linear_acceleration", &c.max_linear_acceleration},
      {"max_angular_acceleration", &c.max_angular_acceleration},
      {"max_unhealthy_frames", &c.max_unhealthy_frames},
      {"target_points", &c.target_points},
      {"initial_voxel_size", &c.initial_voxel_size},
      {"min_voxel_size", &c.min_voxel_size},
      {"max_voxel_size", &c.max_voxel_size},
      {"alpha_human", &c.alpha_human},
      {"alpha_pole_sign", &c.alpha_pole_sign},
      {"alpha_ground", &c.alpha_ground},
      {"alpha_default", &c.alpha_default},
      {"use_semantics", &c.use_semantics},
      {"use_gravity", &c.use_gravity},
      {"gravity_tilt_walk_deg", &c.gravity_tilt_walk_deg},
      {"imu_roll_deg", &c.imu_roll_deg},
      {"imu_pitch_deg", &c.imu_pitch_deg},
      {"imu_yaw_deg", &c.imu_yaw_deg},
      {"imu_attitude_sigma_deg", &c.imu_attitude_sigma_deg},
      {"initial_threshold", &c.initial_threshold},
      {"min_motion", &c.min_motion},
      {"refine_threshold", &c.refine_threshold},
      {"refine_initial_pose", &c.refine_initial_pose},
      {"chunk_radius", &c.chunk_radius},
      {"occupancy_threshold", &c.occupancy_threshold},
      {"min_map_points", &c.min_map_points},
      {"pipelined_map", &c.pipelined_map},
      {"delta_chunks", &c.delta_chunks},
      {"chunk_interval", &c.chunk_interval},
      {"planarity_threshold", &c.planarity_threshold},
      {"point_to_plane", &c.point_to_plane},
      {"sparse_voxel_pairs", &c.sparse_voxel_pairs},
      {"sparse_pairs_along_scan_normal", &c.sparse_pairs_along_scan_normal},
      {"sparse_point_pairs", &c.sparse_point_pairs},
      {"gamma", &c.gamma},
      {"w_lower", &c.w_lower},
      {"max_iterations", &c.max_iterations},
      {"convergence", &c.convergence},
      {"relocalize_candidates", &c.relocalize_candidates},
      {"relocalize_min_fitness", &c.relocalize_min_fitness},
      {"relocalize_max_free", &c.relocalize_max_free},
      {"relocalize_margin", &c.relocalize_margin},
      {"relocalize_scan_lead", &c.relocalize_scan_lead},
      {"relocalize_timeout", &c.relocalize_timeout},
      {"relocalize_voxel_size", &c.relocalize_voxel_size},
      {"relocalize_hint_radius", &c.relocalize_hint_radius},
      {"relocalize_stack_scans", &c.relocalize_stack_scans},
      {"relocalize_confirm_scans", &c.relocalize_confirm_scans},
      {"own_frame_search_period", &c.own_frame_search_period},
      {"own_frame_look_back", &c.own_frame_look_back},
      {"own_frame_look_back_live", &c.own_frame_look_back_live},
      {"own_frame_look_back_gap", &c.own_frame_look_back_gap},
      {"timeout_ms", &c.timeout_ms},
      {"max_attempts", &c.max_attempts},
  };
}

}  // namespace

std::array<double, kNumClasses> classFactors(const OdomConfig& cfg) {
  std::array<double, kNumClasses> alpha{};
  for (int c = 0; c < kNumClasses; ++c) {
    const auto cls = static_cast<std::uint8_t>(c);
    if (!cfg.use_semantics)
      alpha[c] = 1.0;
    else if (isHuman(cls))
      alpha[c] = cfg.alpha_human;
    else if (isPoleOrSign(cls))
      alpha[c] = cfg.alpha_pole_sign;
    else if (isGround(cls))
      alpha[c] = cfg.alpha_ground;
    else
      alpha[c] = cfg.alpha_default;
  }
  return alpha;
}

OdomConfig loadOdomConfig(const std::filesystem::path& file) {
  return loadOdomConfig(std::vector<std::filesystem::path>{file});
}

OdomConfig loadOdomConfig(const std::vector<std::filesystem::path>& files) {
  OdomConfig cfg;
  const YamlFields keys = fields(cfg);
  for (std::size_t i = 0; i < files.size(); ++i) {
    // Only the result is judged: one layer alone may leave a pair of keys inconsistent that
    // the next one completes (a sensor file's voxel sizes, a method file's thresholds).
    std::function<std::string()> check;
    if (i + 1 == files.size()) check = [&cfg] { return validate(cfg); };
    loadYamlFields(files[i], "odom config", keys, check);
  }
  return cfg;
}

std::string validate(const OdomConfig& c) {
  const auto finite_pos = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  if (!std::isfinite(c.min_range) || c.min_range < 0.0) return "min_range must be >= 0";
  if (!finite_pos(c.max_range) || c.max_range <= c.min_range)
    return "max_range must be > min_range";
  if (!(std::abs(c.vertical_angle_correction_deg) <= 5.0))
    return "vertical_angle_correction_deg must be within [-5, 5]";
  if (!finite_pos(c.frame_period)) return "frame_period must be > 0";
  if (!std::isfinite(c.deskew_reference_time)) return "deskew_reference_time must be finite";
  if (!std::isfinite(c.gravity_tilt_walk_deg) || c.gravity_tilt_walk_deg < 0.0)
    return "gravity_tilt_walk_deg must be >= 0";
  int stated = 0;
  for (const double angle : {c.imu_roll_deg, c.imu_pitch_deg, c.imu_yaw_deg}) {
    if (std::isinf(angle) || std::abs(angle) > 360.0)  // NaN: not stated
      return "imu_roll_deg, imu_pitch_deg and imu_yaw_deg must be within [-360, 360]";
    stated += std::isnan(angle) ? 0 : 1;
  }
  if (stated == 1 || stated == 2)
    return "imu_roll_deg, imu_pitch_deg and imu_yaw_deg: state all three or none";
  if (!std::isfinite(c.imu_attitude_sigma_deg) || c.imu_attitude_sigma_deg < 0.0 ||
      c.imu_attitude_sigma_deg > 90.0)
    return "imu_attitude_sigma_deg must be within [0, 90]";
  if (c.deskew_iterations < 1) return "deskew_iterations must be >= 1";
  if (c.chunk_interval < 1) return "chunk_interval must be >= 1";
  if (!std::isfinite(c.sweep_twist_sigma_linear) || c.sweep_twist_sigma_linear < 0.0 ||
      !std::isfinite(c.sweep_twist_sigma_angular) || c.sweep_twist_sigma_angular < 0.0)
    return "sweep_twist_sigma_linear/angular must be >= 0";
  if (!std::isfinite(c.azimuth_start_deg)) return "azimuth_start_deg must be finite";
  if (!unit(c.scan_time_in_sweep)) return "scan_time_in_sweep must be within [0, 1]";
  if (!unit(c.min_inlier_fraction)) return "min_inlier_fraction must be within [0, 1]";
  if (!finite_pos(c.max_residual_ratio)) return "max_residual_ratio must be > 0";
  if (!std::isfinite(c.min_constraint) || c.min_constraint < 0.0)
    return "min_constraint must be >= 0";
  for (const double v : {c.max_linear_speed, c.max_angular_speed, c.max_linear_acceleration,
                         c.max_angular_acceleration})
    if (!finite_pos(v)) return "max_linear/angular_speed/acceleration must be > 0";
  if (c.max_unhealthy_frames < 1) return "max_unhealthy_frames must be >= 1";
  if (c.target_points < 10) return "target_points must be >= 10";
  if (!finite_pos(c.min_voxel_size)) return "min_voxel_size must be > 0";
  if (!finite_pos(c.max_voxel_size) || c.max_voxel_size < c.min_voxel_size)
    return "max_voxel_size must be >= min_voxel_size";
  if (!(c.initial_voxel_size >= c.min_voxel_size && c.initial_voxel_size <= c.max_voxel_size))
    return "initial_voxel_size must be within [min_voxel_size, max_voxel_size]";
  for (const double a : {c.alpha_human, c.alpha_pole_sign, c.alpha_ground, c.alpha_default})
    if (!std::isfinite(a) || a < 0.0 || a > 10.0) return "alpha_* must be within [0, 10]";
  if (!finite_pos(c.initial_threshold)) return "initial_threshold must be > 0";
  if (!std::isfinite(c.min_motion) || c.min_motion < 0.0) return "min_motion must be >= 0";
  if (!std::isfinite(c.refine_threshold) || c.refine_threshold < 0.0)
    return "refine_threshold must be >= 0";
  if (!finite_pos(c.chunk_radius)) return "chunk_radius must be > 0";
  if (!unit(c.occupancy_threshold)) return "occupancy_threshold must be within [0, 1]";
  if (c.min_map_points < 0) return "min_map_points must be >= 0";
  if (!finite_pos(c.planarity_threshold)) return "planarity_threshold must be > 0";
  if (!std::isfinite(c.gamma) || c.gamma < 0.0) return "gamma must be >= 0";
  if (!unit(c.w_lower)) return "w_lower must be within [0, 1]";
  if (c.max_iterations < 1) return "max_iterations must be >= 1";
  if (!finite_pos(c.convergence)) return "convergence must be > 0";
  if (c.relocalize_candidates < 1 || c.relocalize_candidates > 16)
    return "relocalize_candidates must be within [1, 16]";
  if (!unit(c.relocalize_min_fitness)) return "relocalize_min_fitness must be within [0, 1]";
  if (!unit(c.relocalize_max_free)) return "relocalize_max_free must be within [0, 1]";
  if (!unit(c.relocalize_margin)) return "relocalize_margin must be within [0, 1]";
  if (!(c.relocalize_scan_lead > 0.0 && c.relocalize_scan_lead <= c.relocalize_margin))
    return "relocalize_scan_lead must be within (0, relocalize_margin]";
  if (!finite_pos(c.relocalize_timeout)) return "relocalize_timeout must be > 0";
  if (!finite_pos(c.relocalize_voxel_size)) return "relocalize_voxel_size must be > 0";
  if (!finite_pos(c.relocalize_hint_radius)) return "relocalize_hint_radius must be > 0";
  if (c.relocalize_stack_scans < 1 || c.relocalize_stack_scans > 20)
    return "relocalize_stack_scans must be within [1, 20]";
  if (c.relocalize_confirm_scans < 1 || c.relocalize_confirm_scans > 20)
    return "relocalize_confirm_scans must be within [1, 20]";
  if (!finite_pos(c.own_frame_search_period)) return "own_frame_search_period must be > 0";
  if (!(c.own_frame_look_back_gap >= 0.0 && std::isfinite(c.own_frame_look_back_gap)))
    return "own_frame_look_back_gap must be >= 0";
  if (c.timeout_ms < 1) return "timeout_ms must be >= 1";
  if (c.max_attempts < 1) return "max_attempts must be >= 1";
  return {};
}

}  // namespace socc::odom
