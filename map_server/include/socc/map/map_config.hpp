#pragma once
// Parameters of the semantic occupancy grid (YAML: see map_server/config/default.yaml).
#include <filesystem>
#include <string>

namespace socc::map {

struct MapConfig {
  double voxel_size = 0.5;         // [m]
  double max_range = 100.0;        // [m] rays are clipped here; farther points only clear space
  double min_range = 0.0;          // [m] closer points are ignored
  bool raycast = true;             // free-space updates ("cleaning rays")
  bool semantics = true;           // use class-dependent miss probabilities when labels arrive

  double p_hit = 0.55;
  double p_miss = 0.49;            // without semantics / unlabeled voxels
  double p_miss_static = 0.498;    // with semantics: static classes (e.g. building)
  double p_miss_moving = 0.475;    // with semantics: potentially moving classes (e.g. car)
  double clamp_min = 0.12;         // OctoMap-style probability bounds, so the map can change
  double clamp_max = 0.97;
  double occupancy_threshold = 0.5;  // p_occ >= threshold is occupied

  double ema_alpha = 0.8;          // semantic EMA: p' = alpha p + (1 - alpha) p_hat

  // Input limits: requests beyond them are rejected, never partially applied.
  std::size_t max_points_per_scan = 2'000'000;
  double max_abs_coordinate = 1.0e5;  // [m] map-frame bound for poses and points
};

/// Loads a YAML file; unknown keys, bad and out-of-range values throw std::runtime_error
/// naming the file and the key (socc/yaml_fields.hpp). Missing keys keep their defaults.
MapConfig loadMapConfig(const std::filesystem::path& file);
/// Empty when cfg is valid, otherwise the first problem found.
std::string validate(const MapConfig& cfg);

}  // namespace socc::map
