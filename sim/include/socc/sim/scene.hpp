#pragma once
// Scenes: a world built around a route plus the sensor trajectory along it.
//   street   - urban street: road, kerbs and sidewalks, terrain, facades with gaps, fences and
//              hedges, street lamps, traffic signs, trees, parked cars, moving cars and people
//   corridor - a long featureless corridor (walls, floor, ceiling): degenerate along its axis
//   zigzag   - the same corridor along a zigzag route
//   office   - a corridor as in real buildings: recessed doors (some open into rooms), recesses
//              and niches, side corridors, pillars at irregular spacing, beams, furniture
//   indoor   - a room with furniture and pillars
#include <optional>
#include <string>

#include "socc/kitti_io.hpp"
#include "socc/sim/realism.hpp"
#include "socc/sim/trajectory.hpp"
#include "socc/sim/world.hpp"

namespace socc::sim {

enum class SceneType { kStreet, kCorridor, kZigzag, kOffice, kIndoor };
SceneType parseSceneType(const std::string& name);  // throws std::invalid_argument

struct SceneOptions {
  SceneType type = SceneType::kStreet;
  /// "auto" (the scene's default), "straight", "circle", "figure8" or "zigzag".
  std::string route = "auto";
  /// Real trajectory (LiDAR frame) to follow instead of a parametric route; the world is built
  /// around it and it is used at 10 Hz.
  std::optional<Poses> poses;
  std::size_t frames = 100;
  double frame_period = 0.1;    // [s]
  std::optional<double> speed;  // [m/s]; default per scene
  std::uint64_t seed = 1;
  /// The car body's own motion on top of the route (realism "motion"; zero: smooth route).
  MotionErrors body_motion;
};

struct Scene {
  World world;
  Trajectory trajectory;  // sensor pose over time; frame k is at k * frame_period
  /// The buildings' walls are exteriors (street): rooms behind their windows are never entered.
  /// Indoors every wall is an interior one, with the sensor's own free space on both sides.
  bool exterior_walls = false;
};

/// Throws std::invalid_argument on bad options.
Scene buildScene(const SceneOptions& options);

}  // namespace socc::sim
