// Corridor scenes: walls beside the route, an infinite floor and ceiling, nothing else, so the
// geometry constrains little along the corridor axis (the degenerate case of GenZ-ICP).
#include <cmath>

#include "scene_builders.hpp"
#include "socc/sim/path_proximity.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

namespace {
constexpr double kHalfWidth = 1.5;        // [m] corridor half width
constexpr double kCorridorCeiling = 3.0;  // [m] above the floor
constexpr double kTile = 1.0;             // [m] wall tiles along the route
constexpr double kWall = 0.3;             // [m] wall thickness
}  // namespace

World buildCorridorWorld(const Path& route, double sensor_height) {
  const PathProximity near(route, 2.0);
  std::vector<Primitive> walls;
  const double floor_z = route.points().front().position.z() - sensor_height;
  for (double s = 0; s < route.length(); s += kTile) {
    const PathPoint p = route.at(s + kTile / 2);
    for (const double side : {1.0, -1.0}) {
      const double lateral = side * (kHalfWidth + kWall / 2);
      // Skip walls that would cut through another stretch of a looping route.
      if (near.nearOtherPart(p.offset(lateral).head<2>(), kHalfWidth, p.s, 4 * kHalfWidth))
        continue;
      Eigen::Vector3d c = p.offset(lateral);
      c.z() = floor_z + kCorridorCeiling / 2;
      walls.push_back(
          {makeBox(c, {kTile + 0.3, kWall, kCorridorCeiling + 0.2}, p.heading), raw::kBuilding});
    }
  }
  std::vector<Plane> planes = {
      {Eigen::Vector3d::UnitZ(), floor_z, raw::kOtherGround},
      {Eigen::Vector3d::UnitZ(), floor_z + kCorridorCeiling, raw::kOtherStructure}};
  return World(std::move(walls), std::move(planes), nullptr, {}, sensor_height);
}

}  // namespace socc::sim
