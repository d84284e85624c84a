#pragma once
// A simulated world: static primitives in an acceleration grid, infinite planes (floors,
// ceilings) and movers (cars, pedestrians) whose pose depends on time.
#include <memory>
#include <optional>
#include <vector>

#include "socc/sim/path.hpp"
#include "socc/sim/primitive_grid.hpp"

namespace socc::sim {

/// An object driving or walking along a path at constant speed, `lateral` metres left of it.
/// Its parts are given in the object frame (x forward, z up from the ground).
struct Mover {
  std::vector<Primitive> parts;
  double s0 = 0.0;       // arc length at t = 0
  double speed = 0.0;    // [m/s]; negative drives against the path direction (facing backwards)
  double lateral = 0.0;  // [m]
};

/// The world frozen at one instant (movers do not move during a sweep).
class WorldSnapshot {
 public:
  WorldSnapshot(const PrimitiveGrid* statics, const std::vector<Plane>* planes,
                PrimitiveGrid movers)
      : statics_(statics), planes_(planes), movers_(std::move(movers)) {}
  std::optional<Hit> cast(const Ray& ray, double max_range) const;

 private:
  const PrimitiveGrid* statics_;
  const std::vector<Plane>* planes_;
  PrimitiveGrid movers_;
};

class World {
 public:
  World(std::vector<Primitive> statics, std::vector<Plane> planes,
        std::shared_ptr<const Path> mover_path, std::vector<Mover> movers, double sensor_height);

  /// The world at time t [s]; it refers to this World, which must outlive it.
  WorldSnapshot at(double t) const;
  /// The primitives of all movers at time t.
  std::vector<Primitive> moverPrimitives(double t) const;
  const PrimitiveGrid& statics() const { return statics_; }
  const std::vector<Plane>& planes() const { return planes_; }

 private:
  PrimitiveGrid statics_;
  std::vector<Plane> planes_;
  std::shared_ptr<const Path> mover_path_;
  std::vector<Mover> movers_;
  double sensor_height_;  // the ground is this far below the path points
};

}  // namespace socc::sim
