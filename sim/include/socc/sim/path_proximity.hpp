#pragma once
// "Is this spot too close to the route?" queries used while placing objects, so that nothing
// is built on the road, including where a looping route crosses or revisits itself.
#include "socc/sim/path.hpp"
#include "socc/sim/planar_cells.hpp"

namespace socc::sim {

class PathProximity {
 public:
  explicit PathProximity(const Path& path, double cell_size = 4.0);

  /// True when some route point lies within `radius` (horizontally) of xy.
  bool near(const Eigen::Vector2d& xy, double radius) const;
  /// As near(), ignoring route points within `window` metres of arc length s (the stretch the
  /// object is being placed along); finds crossings and revisits.
  bool nearOtherPart(const Eigen::Vector2d& xy, double radius, double s, double window) const;

 private:
  bool search(const Eigen::Vector2d& xy, double radius, const double* s, double window) const;

  const Path& path_;
  PlanarCells cells_;
};

}  // namespace socc::sim
