// The urban street scene. Lateral layout (metres left (+) / right (-) of the route, which is the
// ego lane): road |d| < 6 with traffic lanes at +-3.2 and parking at +-5, kerb and sidewalk
// 6..9 (raised 0.15 m), terrain 9..29, facades from ~10.5 m.
#include <algorithm>
#include <cmath>

#include "scene_builders.hpp"
#include "socc/sim/object_models.hpp"
#include "socc/sim/path_proximity.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

namespace {

constexpr double kRoadHalfWidth = 6.0;
constexpr double kSidewalkWidth = 3.0;
constexpr double kTile = 3.0;  // [m] ground tiles along the route
constexpr double kBuildingClearance = 10.0;

class StreetBuilder {
 public:
  StreetBuilder(const Path& route, double sensor_height, Random& rng)
      : route_(route), near_(route), height_(sensor_height), rng_(rng) {}

  std::vector<Primitive> build() {
    groundTiles();
    for (const double side : {1.0, -1.0}) {
      facades(side);
      roadside(side);
      parkedCars(side);
    }
    return std::move(out_);
  }

 private:
  Eigen::Vector3d ground(const PathPoint& p, double lateral) const {
    Eigen::Vector3d g = p.offset(lateral);
    g.z() -= height_;
    return g;
  }
  void add(const Parts& parts) { out_.insert(out_.end(), parts.begin(), parts.end()); }
  // Slab whose top is `top` above the local ground, inclined at the route's grade (level slabs
  // would make a sloped street a staircase with kerb-high steps every tile).
  void slab(const PathPoint& p, double lateral, double width, double top, std::uint16_t label) {
    const double thickness = 0.4;
    const double rise =
        route_.at(p.s + kTile / 2).position.z() - route_.at(p.s - kTile / 2).position.z();
    const double pitch = std::atan2(rise, kTile);
    Eigen::Vector3d c = ground(p, lateral);
    c.z() += (top - thickness / 2) / std::cos(pitch);
    out_.push_back({makeBox(c, {kTile + 0.4, width, thickness}, p.heading, pitch), label});
  }
  bool clearOfOtherRoads(const PathPoint& p, double lateral, double radius) const {
    return !near_.nearOtherPart(p.offset(lateral).head<2>(), radius, p.s, 25.0);
  }

  void groundTiles() {
    for (double s = 0; s < route_.length(); s += kTile) {
      const PathPoint p = route_.at(s + kTile / 2);
      slab(p, 0.0, 2 * kRoadHalfWidth, 0.0, raw::kRoad);
      for (const double side : {1.0, -1.0}) {
        const double walk = side * (kRoadHalfWidth + kSidewalkWidth / 2);
        if (clearOfOtherRoads(p, walk, kRoadHalfWidth + 1.0))
          slab(p, walk, kSidewalkWidth, 0.15, raw::kSidewalk);
        const double inner = side * 9.5;
        const double outer = side * 28.5;
        if (clearOfOtherRoads(p, inner, 7.0) && clearOfOtherRoads(p, side * 19, 7.0) &&
            clearOfOtherRoads(p, outer, 7.0))
          slab(p, side * 19.0, 20.0, 0.1, raw::kTerrain);
      }
    }
  }

  // True when the rectangle (length x depth at lateral offset, along the route at s) keeps
  // `clearance` from every part of the route.
  bool footprintClear(const PathPoint& p, double lateral, double length, double depth,
                      double clearance) const {
    const Eigen::Vector2d c = p.offset(lateral).head<2>();
    const Eigen::Vector2d ax(std::cos(p.heading), std::sin(p.heading));
    const Eigen::Vector2d ay(-ax.y(), ax.x());
    for (double u = -0.5; u <= 0.5; u += 0.125)
      for (double v = -0.5; v <= 0.5; v += 0.25)
        if (near_.near(c + u * length * ax + v * depth * ay, clearance)) return false;
    return true;
  }

  void facades(double side) {
    for (double s = rng_.uniform(0, 5); s < route_.length();) {
      const double length = rng_.uniform(8, 25);
      const PathPoint p = route_.at(s + length / 2);
      if (rng_.chance(0.8)) {
        const double setback = rng_.uniform(10.5, 13.0);
        const double depth = rng_.uniform(8, 16);
        const double h = rng_.uniform(6, 22);
        const double lateral = side * (setback + depth / 2);
        if (footprintClear(p, lateral, length, depth, kBuildingClearance)) {
          Eigen::Vector3d c = ground(p, lateral);
          c.z() += h / 2 - 1.0;  // reaches 1 m below the ground: no gap on slopes
          out_.push_back({makeBox(c, {length, depth, h + 1.0}, p.heading), raw::kBuilding});
        }
      } else {
        const bool fence = rng_.chance(0.5);
        const double lateral = side * 10.2;
        if (footprintClear(p, lateral, length, 1.0, kBuildingClearance - 1.0)) {
          const double h = fence ? 1.5 : 1.8;
          Eigen::Vector3d c = ground(p, lateral);
          c.z() += h / 2 - 0.2;
          out_.push_back({makeBox(c, {length, fence ? 0.1 : 1.0, h + 0.4}, p.heading),
                          fence ? raw::kFence : raw::kVegetation});
        }
      }
      s += length + rng_.uniform(0.5, 6.0);
    }
  }

  void roadside(double side) {
    // Only its own stretch of route may be as close as the object's lateral offset.
    const auto place = [&](double lateral, double s, const Parts& parts) {
      const PathPoint p = route_.at(s);
      if (!footprintClear(p, lateral, 0.0, 0.0, std::abs(lateral) - 0.3)) return;
      add(placeParts(parts, ground(p, lateral), p.heading));
    };
    for (double s = rng_.uniform(0, 10); s < route_.length(); s += rng_.uniform(20, 35))
      place(side * 6.4, s, streetLampModel());
    for (double s = rng_.uniform(0, 40); s < route_.length(); s += rng_.uniform(40, 80))
      place(side * 6.6, s, trafficSignModel());
    for (double s = rng_.uniform(0, 10); s < route_.length(); s += rng_.uniform(8, 20))
      place(side * 8.3, s, treeModel(rng_));
    for (double s = rng_.uniform(0, 30); s < route_.length(); s += rng_.uniform(20, 60))
      place(side * rng_.uniform(7, 8.5), s, personModel(raw::kPerson));
  }

  void parkedCars(double side) {
    for (double s = rng_.uniform(0, 10); s < route_.length();) {
      if (rng_.chance(0.45)) {
        const PathPoint p = route_.at(s);
        if (footprintClear(p, side * 5.0, 4.3, 1.8, 3.9))
          add(placeParts(carModel(raw::kCar), ground(p, side * 5.0),
                         p.heading + (rng_.chance(0.5) ? 0.0 : M_PI)));
        s += rng_.uniform(5.0, 7.0);
      } else {
        s += rng_.uniform(3.0, 12.0);
      }
    }
  }

  const Path& route_;
  PathProximity near_;
  double height_;
  Random& rng_;
  std::vector<Primitive> out_;
};

std::vector<Mover> streetMovers(const Path& route, Random& rng) {
  std::vector<Mover> movers;
  const double len = route.length();
  const int cars = std::clamp(static_cast<int>(len / 30), 4, 40);
  for (int i = 0; i < cars; ++i) {
    const bool oncoming = rng.chance(0.5);
    const double speed = oncoming ? -rng.uniform(7, 12) : rng.uniform(5, 13);
    movers.push_back(
        {carModel(raw::kMovingCar), rng.uniform(0, len), speed, oncoming ? -3.2 : 3.2});
  }
  const int people = std::clamp(static_cast<int>(len / 25), 4, 40);
  for (int i = 0; i < people; ++i)
    movers.push_back({personModel(raw::kMovingPerson), rng.uniform(0, len),
                      rng.sign() * rng.uniform(0.8, 1.6), rng.sign() * rng.uniform(7.0, 8.5)});
  return movers;
}

}  // namespace

World buildStreetWorld(const std::shared_ptr<const Path>& route, double sensor_height,
                       Random& rng) {
  std::vector<Primitive> statics = StreetBuilder(*route, sensor_height, rng).build();
  std::vector<Mover> movers = streetMovers(*route, rng);
  return World(std::move(statics), {}, route, std::move(movers), sensor_height);
}

}  // namespace socc::sim
