#include "socc/sim/object_models.hpp"

#include <cmath>

#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

namespace {

Shape placeShape(const Shape& shape, const Eigen::Vector3d& ground, double heading) {
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  const auto to_world = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(ground.x() + c * p.x() - s * p.y(), ground.y() + s * p.x() + c * p.y(),
                           ground.z() + p.z());
  };
  if (const auto* b = std::get_if<Box>(&shape)) {
    Box out = *b;
    out.center = to_world(b->center);
    out.cos_yaw = c * b->cos_yaw - s * b->sin_yaw;  // yaw angles add
    out.sin_yaw = s * b->cos_yaw + c * b->sin_yaw;
    return out;
  }
  if (const auto* cy = std::get_if<Cylinder>(&shape)) {
    Cylinder out = *cy;
    out.axis_xy = to_world(Eigen::Vector3d(cy->axis_xy.x(), cy->axis_xy.y(), 0)).head<2>();
    out.z_min += ground.z();
    out.z_max += ground.z();
    return out;
  }
  Sphere out = std::get<Sphere>(shape);
  out.center = to_world(out.center);
  return out;
}

Primitive cylinder(double x, double y, double z0, double z1, double r, std::uint16_t label) {
  return {Cylinder{Eigen::Vector2d(x, y), z0, z1, r}, label};
}

}  // namespace

Parts placeParts(const Parts& parts, const Eigen::Vector3d& ground, double heading) {
  Parts out;
  out.reserve(parts.size());
  for (const auto& p : parts) out.push_back({placeShape(p.shape, ground, heading), p.label});
  return out;
}

Parts carModel(std::uint16_t label) {
  return {{makeBox({0, 0, 0.75}, {4.3, 1.8, 0.8}), label},
          {makeBox({-0.3, 0, 1.4}, {2.3, 1.6, 0.55}), label},
          // Wheels, so that the underside is not a flat slab.
          cylinder(1.35, 0.75, 0.0, 0.35, 0.33, label),
          cylinder(1.35, -0.75, 0.0, 0.35, 0.33, label),
          cylinder(-1.35, 0.75, 0.0, 0.35, 0.33, label),
          cylinder(-1.35, -0.75, 0.0, 0.35, 0.33, label)};
}

Parts personModel(std::uint16_t label) {
  return {cylinder(0, 0, 0.0, 1.5, 0.22, label), {Sphere{{0, 0, 1.65}, 0.13}, label}};
}

Parts treeModel(Random& rng) {
  const double trunk_height = rng.uniform(2.0, 3.5);
  Parts parts = {cylinder(0, 0, -0.2, trunk_height, rng.uniform(0.15, 0.3), raw::kTrunk)};
  const int blobs = 5 + static_cast<int>(rng.uniform(0, 4));
  for (int i = 0; i < blobs; ++i) {
    const Eigen::Vector3d c(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0),
                            trunk_height + 1.0 + rng.uniform(-0.4, 0.8));
    parts.push_back({Sphere{c, rng.uniform(0.8, 1.5)}, raw::kVegetation});
  }
  return parts;
}

Parts streetLampModel() {
  return {cylinder(0, 0, -0.2, 7.0, 0.12, raw::kPole),
          {makeBox({0, 0, 7.05}, {0.5, 0.3, 0.15}), raw::kPole}};
}

Parts trafficSignModel() {
  return {cylinder(0, 0, -0.2, 2.6, 0.04, raw::kPole),
          {makeBox({0.06, 0, 2.3}, {0.04, 0.7, 0.7}), raw::kTrafficSign}};
}

}  // namespace socc::sim
