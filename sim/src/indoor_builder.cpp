// Indoor scene: a room enclosing the route, with tables, chairs, cabinets and pillars kept off
// the route.
#include <algorithm>
#include <cmath>

#include "scene_builders.hpp"
#include "socc/sim/object_models.hpp"
#include "socc/sim/path_proximity.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

namespace {

constexpr double kMargin = 3.5;       // [m] route to wall
constexpr double kRoomCeiling = 2.8;  // [m]
constexpr double kClearance = 1.2;    // [m] furniture to route

Parts table() {
  Parts p = {{makeBox({0, 0, 0.74}, {1.6, 0.8, 0.04}), raw::kOtherObject}};
  for (const double x : {-0.7, 0.7})
    for (const double y : {-0.3, 0.3})
      p.push_back({Cylinder{Eigen::Vector2d(x, y), 0.0, 0.72, 0.03}, raw::kOtherObject});
  return p;
}

Parts chair() {
  return {{makeBox({0, 0, 0.45}, {0.45, 0.45, 0.05}), raw::kOtherObject},
          {makeBox({-0.2, 0, 0.22}, {0.05, 0.45, 0.45}), raw::kOtherObject},
          {makeBox({-0.2, 0, 0.7}, {0.05, 0.45, 0.5}), raw::kOtherObject}};
}

Parts cabinet(Random& rng) {
  const double h = rng.uniform(1.0, 2.0);
  return {{makeBox({0, 0, h / 2}, {0.6, rng.uniform(0.8, 1.6), h}), raw::kOtherObject}};
}

Parts pillar() {
  return {{Cylinder{Eigen::Vector2d::Zero(), -0.1, kRoomCeiling + 0.1, 0.25}, raw::kBuilding}};
}

}  // namespace

World buildIndoorWorld(const Path& route, double sensor_height, Random& rng) {
  Eigen::AlignedBox2d room;
  for (const auto& p : route.points()) room.extend(p.position.head<2>());
  room.min() -= Eigen::Vector2d::Constant(kMargin);
  room.max() += Eigen::Vector2d::Constant(kMargin);
  const double floor_z = route.points().front().position.z() - sensor_height;
  const Eigen::Vector2d size = room.sizes();
  const Eigen::Vector2d mid = room.center();

  std::vector<Primitive> statics;
  const double wall_z = floor_z + kRoomCeiling / 2;
  const auto wall = [&](const Eigen::Vector2d& c, double sx, double sy) {
    statics.push_back(
        {makeBox({c.x(), c.y(), wall_z}, {sx, sy, kRoomCeiling + 0.2}), raw::kBuilding});
  };
  wall({room.min().x() - 0.15, mid.y()}, 0.3, size.y() + 0.6);
  wall({room.max().x() + 0.15, mid.y()}, 0.3, size.y() + 0.6);
  wall({mid.x(), room.min().y() - 0.15}, size.x() + 0.6, 0.3);
  wall({mid.x(), room.max().y() + 0.15}, size.x() + 0.6, 0.3);

  const PathProximity near(route, 1.0);
  const int items = std::clamp(static_cast<int>(size.prod() / 6.0), 6, 60);
  for (int i = 0, tries = 0; i < items && tries < 50 * items; ++tries) {
    const Eigen::Vector2d xy(rng.uniform(room.min().x() + 0.5, room.max().x() - 0.5),
                             rng.uniform(room.min().y() + 0.5, room.max().y() - 0.5));
    const double kind = rng.uniform();
    const double yaw = rng.uniform(-M_PI, M_PI);
    if (near.near(xy, kClearance + 0.9)) continue;
    const Parts parts = kind < 0.3    ? table()
                        : kind < 0.6  ? chair()
                        : kind < 0.85 ? cabinet(rng)
                                      : pillar();
    const Parts placed = placeParts(parts, {xy.x(), xy.y(), floor_z}, yaw);
    statics.insert(statics.end(), placed.begin(), placed.end());
    ++i;
  }
  std::vector<Plane> planes = {
      {Eigen::Vector3d::UnitZ(), floor_z, raw::kOtherGround},
      {Eigen::Vector3d::UnitZ(), floor_z + kRoomCeiling, raw::kOtherStructure}};
  return World(std::move(statics), std::move(planes), nullptr, {}, sensor_height);
}

}  // namespace socc::sim
