#pragma once
// Per-laser calibration of a Velodyne sensor, read from VeloView's XML (db.xml: degrees and
// centimetres) or from the ROS velodyne driver's YAML (radians and metres). Both describe the
// same model of each laser (Velodyne manuals, "calibration"): a vertical angle, an azimuth offset
// and distance / position corrections.
#include <filesystem>
#include <vector>

namespace socc::sensors::velodyne {

struct LaserCalibration {
  double vert_rad = 0.0;  // elevation of the beam
  double rot_rad = 0.0;   // azimuth offset: the beam points at azimuth - rot_rad
  double dist_m = 0.0;    // added to every measured distance
  double dist_x_m = 0.0;  // two-point distance corrections of the HDL-64E (0: none)
  double dist_y_m = 0.0;
  double vert_offset_m = 0.0;     // the emitter's height above the sensor's origin plane
  double horiz_offset_m = 0.0;    // its sideways offset from the rotation axis
  double focal_distance_m = 0.0;  // intensity corrections (HDL-64E); kept, not applied
  double focal_slope = 0.0;
  bool enabled = true;  // VeloView's enabled_ list (VLP-16 files list 64 lasers, 16 enabled)
};

struct Calibration {
  std::vector<LaserCalibration> lasers;  // by laser id
  double distance_resolution_m = 0.0;    // 0: the file does not say (the model's own is used)
};

/// Reads a VeloView XML (.xml) or ROS velodyne YAML (.yaml / .yml) calibration. Throws
/// std::runtime_error naming the file and the problem (unreadable, no lasers, duplicate or
/// missing laser ids, non-finite or out-of-range values).
Calibration loadCalibration(const std::filesystem::path& file);

}  // namespace socc::sensors::velodyne
