#pragma once
// SOCC-ICP scan-to-map registration: GenZ-ICP-style adaptive mix of point-to-plane (planar
// voxels) and point-to-point residuals, alpha = N_pl / (N_pl + N_po), each correspondence
// weighted by w_gm * w_occ * w_sem; Gauss-Newton on SE(3) (6x6 normal equations, LDLT).
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "socc/odom/local_map.hpp"
#include "socc/odom/scan_normals.hpp"
#include "socc/odom/se3.hpp"
#include "socc/point_cloud.hpp"

namespace socc::odom {

/// A gravity reference's hold on the sensor's tilt (tilt_reference.hpp): the sensor's measured
/// up, rotated into the map, is pulled towards the map's up so that the registration's tilt
/// moves `gain` of the way from where the scan alone puts it to where the reference does.
struct TiltPrior {
  Eigen::Vector3d map_up = Eigen::Vector3d::UnitZ();     // unit, map frame
  Eigen::Vector3d sensor_up = Eigen::Vector3d::UnitZ();  // unit, sensor frame at the pose
  double gain = 0.0;                                     // in [0, 1)
};

struct RegistrationParams {
  double planarity_threshold = 0.1;
  double gamma = 1.5;
  double w_lower = 0.25;
  int max_iterations = 100;
  double convergence = 1e-4;   // ||dx|| below this stops
  bool point_to_plane = true;  // false: point-to-point only (a KISS-ICP-like baseline)
  // Pairs with voxels of unknown geometry (fewer than 5 points: planarity < 0), as the paper
  // does. Their first point is one sample of an unknown surface, and pulling a sparse scan's rings
  // onto the map's rings favours standing still; but on a degenerate street a VLP-16 needs them
  // (docs/robustness.md). false: weight 0.
  bool sparse_voxel_pairs = true;
  // ... also where the scan point has no surface normal of its own (a ring's line, clutter): a
  // point pair between two samples of unknown surfaces. On a sparse sensor these are mostly far
  // ground and facade rings, whose place depends on the sensor's height and tilt, so they hold
  // the sensor at the previous frames' tilt (a VLP-16 lagged a 1.5 deg roll by 2-3 s, 2.4 % drift
  // without semantics; docs/robustness.md "Sparse point pairs"). false: weight 0.
  bool sparse_point_pairs = false;
  // The iterates of earlier runs from other guesses on the same points: an iteration that comes
  // within join_distance (twist norm) of one ends, `joined`. Each step is a function of the pose
  // alone, so from there it would follow that run into the basin it already explored. A run
  // records its own iterates in RegistrationResult::path when join_distance > 0.
  std::vector<Eigen::Isometry3d> join_path;
  double join_distance = 0.0;
  // A direction (map frame, unit; zero: none) along which the sensor's position is held towards
  // hold_position: a degenerate registration's weakest direction, where the scan's evidence is
  // too weak to outweigh the motion model's prediction (docs/robustness.md, "Degenerate frames
  // coast").
  Eigen::Vector3d hold_direction = Eigen::Vector3d::Zero();
  Eigen::Vector3d hold_position = Eigen::Vector3d::Zero();
  // What the hold is worth, in planar pairs of full weight (a prior on the position along the
  // direction, in the data's units); 0: no hold.
  double hold_pairs = 0.0;
  // The gravity reference's hold on roll and pitch; none: the scan alone.
  std::optional<TiltPrior> tilt = std::nullopt;
};

struct RegistrationResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // map_T_sensor
  int iterations = 0;
  bool converged = false;  // ||dx|| < convergence
  bool stalled = false;    // stopped because the iteration cycled back to a recent pose
  bool joined = false;     // stopped next to one of RegistrationParams::join_path
  int planar = 0;          // correspondences of the last iteration
  int non_planar = 0;
  double alpha = 0.0;         // N_pl / (N_pl + N_po) of the last iteration
  double rms_residual = 0.0;  // [m] of the last iteration's correspondences (unweighted)
  // Weighted normal matrix J^T W J of the last iteration (translation first): how well each
  // direction of the pose is constrained (degeneracy check).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  // The point-to-plane part alone: a point-to-point pair with a voxel's first point seems to
  // constrain every direction even on a plane, so only this part shows what the geometry pins.
  Eigen::Matrix<double, 6, 6> planar_information = Eigen::Matrix<double, 6, 6>::Zero();
  // Continuous-time registration only (SweepTwistPrior given): the correction of the body twist
  // the scan was deskewed with [per second, translation first].
  Vector6d twist_correction = Vector6d::Zero();
  // The poses the iteration went through (RegistrationParams::join_distance > 0 only).
  std::vector<Eigen::Isometry3d> path;
  int correspondences() const { return planar + non_planar; }
};

/// Continuous-time registration of a sweep (the scan must carry times relative to the pose's
/// instant, i.e. the middle of the sweep). Besides the pose it estimates a correction c of the
/// body twist the scan was deskewed with: a point taken at time s moves by s * c. A twist
/// measured between two poses lags the sweep by half a frame where the motion accelerates; the
/// scan's own shape says how it moved while it was taken. The prior keeps (twist + c) near a
/// measured twist, with a standard deviation per component, so that what the scan does not
/// constrain (a straight corridor) stays as measured.
struct SweepTwistPrior {
  Vector6d offset = Vector6d::Zero();  // deskew twist minus the prior's mean [per second]
  Vector6d sigma = Vector6d::Ones();   // standard deviation of the prior [m/s, rad/s]
};

/// One correspondence's contribution, exposed so tests can check the formulas.
struct Correspondence {
  bool planar = false;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // of a planar pair (the voxel's or the scan's)
  double squared_residual = 0.0;
  double weight = 0.0;  // w_gm * w_occ * w_sem
};
/// Classifies and weighs the pair (map-frame point with its label, voxel) with sigma's kernel.
/// scan_normal (map frame, zero when none): the scan's surface at the point (scan_normals.hpp),
/// along which a voxel of unknown geometry is paired instead of to its first point.
Correspondence evaluateCorrespondence(const Eigen::Vector3d& point, std::uint8_t label,
                                      const MapVoxel& voxel, double sigma,
                                      const RegistrationParams& params,
                                      const Eigen::Vector3d& scan_normal = Eigen::Vector3d::Zero());

/// Registers scan (sensor frame, labels optional) against map from initial_guess; sigma is the
/// adaptive threshold (correspondences within 3 sigma, kernel sigma / 3). scan_normals: none,
/// or the scan's surface normals (sensor frame; asked for only where a voxel's geometry is
/// unknown).
RegistrationResult registerScan(const LabeledCloud& scan, const LocalMap& map,
                                const Eigen::Isometry3d& initial_guess, double sigma,
                                const RegistrationParams& params,
                                const SweepTwistPrior* twist_prior = nullptr,
                                const ScanNormals* scan_normals = nullptr);

}  // namespace socc::odom
