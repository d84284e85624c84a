#include "socc/odom/odom_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <variant>

namespace socc::odom {
namespace {

// Every YAML key maps to exactly one field, so unknown keys can be reported.
using Field = std::variant<double OdomConfig::*, int OdomConfig::*, bool OdomConfig::*>;

const std::map<std::string, Field>& fields() {
  static const std::map<std::string, Field> table = {
      {"min_range", &OdomConfig::min_range},
      {"max_range", &OdomConfig::max_range},
      {"deskew", &OdomConfig::deskew},
      {"frame_period", &OdomConfig::frame_period},
      {"deskew_reference_time", &OdomConfig::deskew_reference_time},
      {"deskew_iterations", &OdomConfig::deskew_iterations},
      {"azimuth_times", &OdomConfig::azimuth_times},
      {"azimuth_start_deg", &OdomConfig::azimuth_start_deg},
      {"azimuth_clockwise", &OdomConfig::azimuth_clockwise},
      {"scan_time_in_sweep", &OdomConfig::scan_time_in_sweep},
      {"min_inlier_fraction", &OdomConfig::min_inlier_fraction},
      {"max_residual_ratio", &OdomConfig::max_residual_ratio},
      {"min_constraint", &OdomConfig::min_constraint},
      {"max_linear_speed", &OdomConfig::max_linear_speed},
      {"max_angular_speed", &OdomConfig::max_angular_speed},
      {"max_linear_acceleration", &OdomConfig::max_linear_acceleration},
      {"max_angular_acceleration", &OdomConfig::max_angular_acceleration},
      {"max_unhealthy_frames", &OdomConfig::max_unhealthy_frames},
      {"target_points", &OdomConfig::target_points},
      {"initial_voxel_size", &OdomConfig::initial_voxel_size},
      {"min_voxel_size", &OdomConfig::min_voxel_size},
      {"max_voxel_size", &OdomConfig::max_voxel_size},
      {"alpha_human", &OdomConfig::alpha_human},
      {"alpha_pole_sign", &OdomConfig::alpha_pole_sign},
      {"alpha_ground", &OdomConfig::alpha_ground},
      {"alpha_default", &OdomConfig::alpha_default},
      {"use_semantics", &OdomConfig::use_semantics},
      {"initial_threshold", &OdomConfig::initial_threshold},
      {"min_motion", &OdomConfig::min_motion},
      {"refine_threshold", &OdomConfig::refine_threshold},
      {"refine_initial_pose", &OdomConfig::refine_initial_pose},
      {"chunk_radius", &OdomConfig::chunk_radius},
      {"occupancy_threshold", &OdomConfig::occupancy_threshold},
      {"min_map_points", &OdomConfig::min_map_points},
      {"planarity_threshold", &OdomConfig::planarity_threshold},
      {"point_to_plane", &OdomConfig::point_to_plane},
      {"sparse_voxel_pairs", &OdomConfig::sparse_voxel_pairs},
      {"gamma", &OdomConfig::gamma},
      {"w_lower", &OdomConfig::w_lower},
      {"max_iterations", &OdomConfig::max_iterations},
      {"convergence", &OdomConfig::convergence},
      {"relocalize_candidates", &OdomConfig::relocalize_candidates},
      {"relocalize_min_fitness", &OdomConfig::relocalize_min_fitness},
      {"relocalize_max_free", &OdomConfig::relocalize_max_free},
      {"relocalize_margin", &OdomConfig::relocalize_margin},
      {"relocalize_timeout", &OdomConfig::relocalize_timeout},
      {"relocalize_voxel_size", &OdomConfig::relocalize_voxel_size},
      {"relocalize_hint_radius", &OdomConfig::relocalize_hint_radius},
      {"timeout_ms", &OdomConfig::timeout_ms},
      {"max_attempts", &OdomConfig::max_attempts},
  };
  return table;
}

template <typename T>
T as(const YAML::Node& node, const std::string& key) {
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error("key '" + key + "' has a value of the wrong type");
  }
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
  const std::string where = file.string() + ": ";
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(where + "cannot parse YAML: " + e.what());
  }
  OdomConfig cfg;
  if (root.IsNull()) return cfg;  // empty file: all defaults
  if (!root.IsMap()) throw std::runtime_error(where + "expected a map of key: value");
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto it = fields().find(key);
    if (it == fields().end()) throw std::runtime_error(where + "unknown key '" + key + "'");
    try {
      std::visit(
          [&](auto member) {
            using T = std::remove_reference_t<decltype(cfg.*member)>;
            cfg.*member = as<T>(kv.second, key);
          },
          it->second);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(where + e.what());
    }
  }
  if (const std::string problem = validate(cfg); !problem.empty())
    throw std::runtime_error(where + problem);
  return cfg;
}

std::string validate(const OdomConfig& c) {
  const auto finite_pos = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  if (!std::isfinite(c.min_range) || c.min_range < 0.0) return "min_range must be >= 0";
  if (!finite_pos(c.max_range) || c.max_range <= c.min_range)
    return "max_range must be > min_range";
  if (!finite_pos(c.frame_period)) return "frame_period must be > 0";
  if (!std::isfinite(c.deskew_reference_time)) return "deskew_reference_time must be finite";
  if (c.deskew_iterations < 1) return "deskew_iterations must be >= 1";
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
  if (!finite_pos(c.relocalize_timeout)) return "relocalize_timeout must be > 0";
  if (!finite_pos(c.relocalize_voxel_size)) return "relocalize_voxel_size must be > 0";
  if (!finite_pos(c.relocalize_hint_radius)) return "relocalize_hint_radius must be > 0";
  if (c.timeout_ms < 1) return "timeout_ms must be >= 1";
  if (c.max_attempts < 1) return "max_attempts must be >= 1";
  return {};
}

}  // namespace socc::odom
