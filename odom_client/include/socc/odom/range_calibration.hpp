#pragma once
// Per-laser range calibration, unsupervised (docs/robustness.md "Per-laser range calibration
// between the lasers"). A multi-beam LiDAR's lasers each carry a small range offset and scale
// left by its factory calibration (HDL-64: cm and ~0.2 %). They do not act as one common scale:
// a wall ahead enters the map through the near-horizontal lasers that see it first, from far
// away, and is matched later by other lasers from near, so the odometry reads distances with the
// scale of the far-seeing lasers, not the lasers' mean. Lasers that disagree about one surface
// are observable: after each registration the scan's points on the map's walls are grouped by
// piece of wall, and per laser an offset and a scale (and, as a nuisance, an azimuth offset) are
// fitted by least squares over the last frames, each piece's plane offset a free unknown, so
// that only the lasers' differences on one wall count (after Levinson & Thrun, RSS 2010). The
// map's points are no reference: each came from whichever laser first saw it, with its error
// (a fit against them kept part of each laser's error: docs/robustness.md, "tried, not kept").
// A laser is known by its elevation (a bin of the point's elevation angle: scans carry no laser
// index, e.g. KITTI's .bin files). A common offset and scale of all lasers is not observable (it
// scales the world); the corrections keep the lasers' mean, each laser weighted by how well it
// is known (the far-seeing lasers, whose scale the world has); a laser takes that shift only in
// what its own evidence determines, so one seen little keeps its factory calibration.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "socc/odom/local_map.hpp"
#include "socc/point_cloud.hpp"
#include "socc/voxel.hpp"

namespace socc::odom {

struct RangeCalibrationParams {
  double bin_deg = 0.1;         // [deg] elevation bin: one laser, or two within this of each other
  double memory_frames = 50.0;  // the fit's evidence fades with this time constant [frames]
  std::size_t samples = 8000;   // points looked up in the map per frame (evenly spread)
  double min_range = 10.0;      // [m] nearer points say little about a scale
  double max_distance = 1.0;    // [m] to the voxel's first point
  double surface_size = 2.0;    // [m] the cells in which points of one facing share one plane
  double max_residual = 0.2;    // [m] along the voxel's normal
  double max_step = 0.05;       // [m] a point's or its map voxel's distance from the median of
                                //   its piece of wall, plus max_scale_error x range: one plane
  double max_scale_error = 0.005;  // a laser's largest scale error
  double min_incidence = 0.5;      // |normal . ray|: the surface faces the ray
  double max_normal_z = 0.3;       // walls only (a piece's mean normal; one voxel's may lean
                                   //   twice as far): on the ground a laser's elevation error
                                   //   looks like a range error
  double planarity_threshold = 0.1;
  // The spread of a sensor's lasers' range offsets and scales that factory calibrations leave
  // (HDL-64: 2 cm, 0.2 %; sim/README.md "Realism" gives the sources): the fit's prior. A wider
  // one (5 cm, 0.5 %) let lasers seen only near the ground drift to 3 % (docs/robustness.md).
  double offset_spread = 0.02;  // [m]
  double scale_spread = 0.002;
  double noise = 0.03;  // [m] one residual's standard deviation
  int fit_every = 5;    // [frames] between solves of the joint problem
};

class RangeCalibration {
 public:
  explicit RangeCalibration(const RangeCalibrationParams& params = {});

  /// Whether the lasers have been fitted (from then on apply() moves the points of every laser
  /// seen on a wall; before, it leaves the cloud as it is).
  bool corrects() const { return fitted_; }
  /// Moves every point of cloud (sensor frame) along its ray by its laser's correction.
  void apply(LabeledCloud& cloud) const;
  /// Compares a registered scan's lasers with each other on the map's walls: raw as apply() left
  /// it (sensor frame, before deskew), placed the same points deskewed (sensor frame at pose,
  /// same order). map gives each point's surface, not its position (see the .cpp).
  void observe(const Points& raw, const Points& placed, const Eigen::Isometry3d& pose,
               const LocalMap& map);

  struct Laser {
    double elevation_deg;  // the bin's centre
    double offset;         // [m] subtracted from its ranges
    double scale;          // subtracted from its ranges as scale * range
  };
  /// The lasers (bins) seen on walls so far, by elevation, with their corrections (zero until
  /// the first fit).
  std::vector<Laser> lasers() const;

 private:
  // One scan point on a map wall, as the uncorrected point would be (the fit is of the laser's
  // whole error, not of its change).
  struct Sample {
    VoxelIndex cell[2];  // the piece of wall it lies on: its cell in each grid,
    int sector;          //   and its facing
    int laser;
    Eigen::Vector3d point;    // world frame
    Eigen::Vector3d anchor;   // its map voxel's point: which plane it is on
    Eigen::Vector3d ray;      // sensor to point, world frame: d point / d range scale
    Eigen::Vector3d azimuth;  // d point / d azimuth
    Eigen::Vector3d normal;   // the map's, facing the sensor
  };
  int binOf(const Eigen::Vector3f& p) const;
  int laserOf(int bin);
  // [m] how much too long laser's ranges of this length are (its correction).
  double rangeError(int laser, double range) const;
  std::vector<Sample> collect(const Points& raw, const Points& placed,
                              const Eigen::Isometry3d& pose, const LocalMap& map);
  void accumulate(std::vector<Sample>& samples);
  void accumulate(std::vector<Sample>& samples, int grid);
  // The samples of one piece of wall, their plane's offset eliminated.
  void addSurface(std::vector<Sample>::const_iterator begin,
                  std::vector<Sample>::const_iterator end);
  void fit();

  RangeCalibrationParams params_;
  std::vector<int> tangent_bins_;  // the bin of an elevation's tangent, in slots (binOf)
  std::vector<int> laser_of_bin_;  // -1: no laser seen in the bin yet
  Eigen::MatrixXd info_;           // sum of g g^T over all lasers' errors, surfaces eliminated
  Eigen::VectorXd evidence_;       // sum of g * residual
  std::vector<Eigen::Vector2d> corrections_;  // offset, scale by laser
  bool fitted_ = false;                       // corrects()
  int frames_ = 0;
};

/// Writes lasers as text, one line per laser: elevation [deg], offset [m], scale, under a
/// header that says how a range is corrected. Throws std::runtime_error when path cannot be
/// written.
void writeRangeCalibration(const std::string& path,
                           const std::vector<RangeCalibration::Laser>& lasers);

}  // namespace socc::odom
