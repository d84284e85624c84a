#include "socc/sim/room_model.hpp"

#include <algorithm>
#include <cmath>

namespace socc::sim {

namespace {

// Distance along a ray at coordinate u (measured from a cell grid's origin, cells of size
// `cell`, the grid ending at `end`) moving at rate du per metre to the next cell boundary.
double toNextBoundary(double u, double du, double cell, double end) {
  if (std::abs(du) < 1e-9) return kInf;
  const double k = std::floor(u / cell);
  if (du > 0.0) return std::max(0.0, (std::min((k + 1.0) * cell, end) - u) / du);
  return std::max(0.0, (u - std::max(k * cell, 0.0)) / -du);
}

}  // namespace

std::optional<double> roomTravel(const Ray& ray, double range, const Box& building,
                                 const RoomLayout& rooms) {
  // Into the box frame (rotated by -yaw about the centre), origin at the box's lowest corner.
  const Eigen::Vector3d hit =
      toBoxFrame(building, ray.origin + range * ray.direction - building.center);
  const Eigen::Vector3d dir = toBoxFrame(building, ray.direction);
  const Eigen::Vector3d& half = building.half_extents;
  // The face entered: the axis on which the hit lies at the box's surface.
  const Eigen::Vector3d depth = hit.cwiseAbs().cwiseQuotient(half);
  int face = 0;
  depth.maxCoeff(&face);
  if (face == 2) return std::nullopt;  // roof or base: no windows
  const double cosine = std::abs(dir[face]);
  if (cosine < rooms.grazing_cosine) return std::nullopt;
  const int along = 1 - face;
  const Eigen::Vector3d corner = hit + half;                             // in [0, 2 half]
  const double back = std::min(rooms.depth, 2.0 * half[face]) / cosine;  // within the building
  const double side = toNextBoundary(corner[along], dir[along], rooms.width, 2.0 * half[along]);
  const double floors = toNextBoundary(corner.z(), dir.z(), rooms.storey, 2.0 * half.z());
  return std::min({back, side, floors});
}

}  // namespace socc::sim
