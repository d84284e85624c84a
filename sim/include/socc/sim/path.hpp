#pragma once
// A 3D polyline parametrised by arc length: the route a sensor follows and that a world is
// built around (streets along it, corridor walls beside it, movers driving on it).
#include <Eigen/Core>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc::sim {

struct PathPoint {
  Eigen::Vector3d position;  // of the sensor route (the ground lies sensor-height below)
  double heading = 0.0;      // yaw of the tangent [rad]
  double s = 0.0;            // arc length [m]

  /// Point `lateral` metres to the left of the route (positive = left of the heading).
  Eigen::Vector3d offset(double lateral) const;
};

class Path {
 public:
  /// points: at least 2, spaced finely enough to be smooth. closed: the route loops back to its
  /// start (the last point joins the first; arc lengths then wrap after loopLength()).
  Path(const std::vector<Eigen::Vector3d>& points, bool closed);

  PathPoint at(double s) const;  // interpolated; wraps when closed, clamps otherwise
  /// Arc length from the first to the last point (what the worlds are built along).
  double length() const { return points_.back().s; }
  /// Arc length after which at() repeats: length() plus, when closed, the closing segment.
  double loopLength() const { return loop_length_; }
  bool closed() const { return closed_; }
  const std::vector<PathPoint>& points() const { return points_; }

 private:
  std::vector<PathPoint> points_;
  bool closed_;
  double loop_length_ = 0.0;
};

/// Along +x from x = 0, `length` metres, at height z.
Path straightPath(double length, double z);
/// Counter-clockwise circle through the origin heading +x; closed.
Path circlePath(double radius, double z);
/// Figure eight of two lobes of the given radius, crossing itself at the origin; closed.
Path figureEightPath(double radius, double z);
/// Zigzag along +x: straight legs at about +-30 deg with rounded corners every period/2.
Path zigzagPath(double length, double period, double z);
/// Positions of the given poses, extended straight by `margin` metres at both ends so that the
/// world continues beyond the recorded route.
Path posePath(const Poses& poses, double margin);

}  // namespace socc::sim
