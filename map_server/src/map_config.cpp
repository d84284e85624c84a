#include "socc/map/map_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

namespace socc::map {
namespace {

bool inOpen(double v, double lo, double hi) {
  return v > lo && v < hi;
}

template <typename T>
void read(const YAML::Node& node, const std::string& key, T& out) {
  try {
    out = node.as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error("map config key '" + key + "': bad value '" +
                             (node.IsScalar() ? node.Scalar() : std::string("<non-scalar>")) + "'");
  }
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
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw std::runtime_error("cannot read map config " + file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("map config " + file.string() + ": " + e.what());
  }
  MapConfig c;
  if (root.IsNull()) return c;  // empty file: all defaults
  if (!root.IsMap()) throw std::runtime_error("map config " + file.string() + " is not a mapping");

  using Setter = std::function<void(const YAML::Node&, const std::string&)>;
  const auto d = [](double& v) -> Setter {
    return [&v](const YAML::Node& n, const std::string& k) { read(n, k, v); };
  };
  const std::map<std::string, Setter> setters = {
      {"voxel_size", d(c.voxel_size)},
      {"max_range", d(c.max_range)},
      {"min_range", d(c.min_range)},
      {"raycast", [&c](const YAML::Node& n, const std::string& k) { read(n, k, c.raycast); }},
      {"semantics", [&c](const YAML::Node& n, const std::string& k) { read(n, k, c.semantics); }},
      {"p_hit", d(c.p_hit)},
      {"p_miss", d(c.p_miss)},
      {"p_miss_static", d(c.p_miss_static)},
      {"p_miss_moving", d(c.p_miss_moving)},
      {"clamp_min", d(c.clamp_min)},
      {"clamp_max", d(c.clamp_max)},
      {"occupancy_threshold", d(c.occupancy_threshold)},
      {"ema_alpha", d(c.ema_alpha)},
      {"max_points_per_scan",
       [&c](const YAML::Node& n, const std::string& k) {
         long long v = 0;
         read(n, k, v);
         if (v <= 0) throw std::runtime_error("map config key '" + k + "' must be positive");
         c.max_points_per_scan = static_cast<std::size_t>(v);
       }},
      {"max_abs_coordinate", d(c.max_abs_coordinate)},
  };
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto it = setters.find(key);
    if (it == setters.end())
      throw std::runtime_error("map config " + file.string() + ": unknown key '" + key + "'");
    it->second(kv.second, key);
  }
  if (const std::string err = validate(c); !err.empty())
    throw std::runtime_error("map config " + file.string() + ": " + err);
  return c;
}

}  // namespace socc::map
