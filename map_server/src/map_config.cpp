#include "socc/map/map_config.hpp"

#include <cmath>

#include "socc/yaml_fields.hpp"

namespace socc::map {
namespace {

bool inOpen(double v, double lo, double hi) {
  return v > lo && v < hi;
}

}  // namespace

std::string validate(const MapConfig& c) {
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(c.voxel_size) || c.voxel_size < 0.01 || c.voxel_size > 100.0)
    return "voxel_size must be in [0.01, 100] m";
  if (!finite(c.max_range) || c.max_range <= 0.0) return "max_range must be > 0";
  if (!finite(c.min_range) || c.min_range < 0.0 || c.min_range >= c.max_range)
    return "min_range must be in [0, max_range)";
  if (!inOpen(c.p_hit, 0.5, 1.0)) return "p_hit must be in (0.5, 1)";
  if (!inOpen(c.p_miss, 0.0, 0.5)) return "p_miss must be in (0, 0.5)";
  if (!inOpen(c.p_miss_static, 0.0, 0.5)) return "p_miss_static must be in (0, 0.5)";
  if (!inOpen(c.p_miss_moving, 0.0, 0.5)) return "p_miss_moving must be in (0, 0.5)";
  if (!inOpen(c.clamp_min, 0.0, 0.5)) return "clamp_min must be in (0, 0.5)";
  if (!inOpen(c.clamp_max, 0.5, 1.0)) return "clamp_max must be in (0.5, 1)";
  if (!(c.occupancy_threshold > c.clamp_min && c.occupancy_threshold < c.clamp_max))
    return "occupancy_threshold must be in (clamp_min, clamp_max)";
  if (!(c.ema_alpha >= 0.0 && c.ema_alpha <= 1.0)) return "ema_alpha must be in [0, 1]";
  if (c.max_points_per_scan == 0 || c.max_points_per_scan > 100'000'000)
    return "max_points_per_scan must be in [1, 1e8]";
  if (!finite(c.max_abs_coordinate) || c.max_abs_coordinate <= 0.0)
    return "max_abs_coordinate must be > 0";
  // Voxel indices (and rays up to max_range beyond the bound) must fit comfortably in int32.
  if ((c.max_abs_coordinate + c.max_range) / c.voxel_size > 1.0e8)
    return "(max_abs_coordinate + max_range) / voxel_size must be <= 1e8";
  return {};
}

MapConfig loadMapConfig(const std::filesystem::path& file) {
  MapConfig c;
  loadYamlFields(file, "map config",
                 {
                     {"voxel_size", &c.voxel_size},
                     {"max_range", &c.max_range},
                     {"min_range", &c.min_range},
                     {"raycast", &c.raycast},
                     {"semantics", &c.semantics},
                     {"p_hit", &c.p_hit},
                     {"p_miss", &c.p_miss},
                     {"p_miss_static", &c.p_miss_static},
                     {"p_miss_moving", &c.p_miss_moving},
                     {"clamp_min", &c.clamp_min},
                     {"clamp_max", &c.clamp_max},
                     {"occupancy_threshold", &c.occupancy_threshold},
                     {"ema_alpha", &c.ema_alpha},
                     {"max_points_per_scan", &c.max_points_per_scan},
                     {"max_abs_coordinate", &c.max_abs_coordinate},
                 },
                 [&c] { return validate(c); });
  return c;
}

}  // namespace socc::map
