#pragma once
// Settings of the consistency service (docs/consistency.md; `consistency:` in server.yaml).
#include <cstddef>

#include "scan_context.hpp"

namespace socc::consistency {

struct ConsistencyParams {
  bool enabled = false;  // off by default (docs/consistency.md)

  // Map correction: after a closure that moves some keyframe's scan by more than
  // rebuild_min_shift (translation plus rotation at rebuild_lever metres), the grid is rebuilt
  // from the keyframe scans at their optimized poses; each kept scan is downsampled per class
  // to rebuild_voxel (the map's voxels keep their statistics from several points each).
  bool correct_grid = true;
  double rebuild_voxel = 0.1;      // [m]
  double rebuild_min_shift = 0.1;  // [m]
  double rebuild_lever = 20.0;     // [m]
  // Region rebuilds: the worker keeps its last rebuilt grid, and the next rebuild integrates
  // again only where keyframes moved more than rebuild_region_shift (grid_rebuild.hpp,
  // updateGrid); off: every rebuild is of the whole map (and the worker keeps no copy).
  bool rebuild_region = true;
  double rebuild_region_shift = 0.05;  // [m] (at rebuild_lever)
  // A region reaching more than this share of the keyframes is rebuilt whole: integrating into
  // a region of a populated grid costs more per scan than into an empty one.
  double rebuild_region_max_share = 0.75;
  // The correction a robot is told fits its keyframes within this much of its path before the
  // last (correction_fit.hpp): the grid it registers against next.
  double correction_window = 30.0;  // [m]
  // While keyframes wait for the worker (a merged robot's kept keyframes arrive as a burst), a
  // rebuild a closure made due waits for the queue to drain, at most this long: one rebuild
  // then takes the closures of the whole backlog instead of one per closure.
  double rebuild_max_wait = 10.0;  // [s]

  // Keyframes: a robot's integration becomes one when it moved or turned this much since its
  // last keyframe.
  double keyframe_distance = 3.0;  // [m]
  double keyframe_angle = 0.5;     // [rad]
  double keyframe_voxel = 0.4;     // [m] the keyframe's scan is downsampled to this grid
  double keyframe_range = 60.0;    // [m] farther points are not kept
  ScanContextParams descriptor;
  // Full clouds waiting for the worker (1.6 MB for an HDL-64 scan). When the worker falls this
  // far behind, a new keyframe's cloud is reduced on arrival, on the map's thread, to what the
  // worker keeps of it (keyframe_reduction.hpp: 0.6 MB for HDL-64) and queued so: it keeps its
  // scan and the queue's memory stays bounded per keyframe.
  int max_pending_scans = 64;

  // Candidates: a robot's own keyframe only after it travelled this far since (a loop, not the
  // last few metres of its path).
  double min_loop_travel = 50.0;  // [m]
  // Around the estimated position: base radius plus this share of the path travelled between
  // the two keyframes (odometry drift), at most max_search_radius.
  double search_radius = 8.0;  // [m]
  double drift_share = 0.02;
  double max_search_radius = 40.0;       // [m]
  double max_descriptor_distance = 0.3;  // Scan Context distance of a place candidate
  int descriptor_candidates = 2;         // best ring-key matches compared in full
  // After a verified closure, the robot's next attempt waits until it travelled this far.
  double closure_spacing = 6.0;  // [m]
  int submap_neighbours = 2;     // keyframes on each side of the candidate in its submap
  double chunk_radius = 60.0;    // [m] registration target around the guess

  // Edge uncertainties: odometry per metre travelled (plus a floor), loop closures fixed.
  double odometry_sigma_t = 0.02;          // [m] + per metre below
  double odometry_sigma_t_per_m = 0.01;    // [m/m]
  double odometry_sigma_r = 0.002;         // [rad] + per metre below
  double odometry_sigma_r_per_m = 0.0005;  // [rad/m]
  // Odometry edges that do not see the shared map (odometry_edge.hpp): each keyframe's scan is
  // registered against its predecessor's; where the result differs from the integrated relative
  // pose by more than snap_min_t or snap_min_r (the registration's noise), the edge measures the
  // scan-to-scan pose (the client snapped onto the old map), else it keeps the integrated one.
  // snap_min_r is on the heading (rotation about the sensor's z): roll and pitch disagree by
  // noise alone. Noise measured on the KITTI-00 shape (HDL-64, 368 edges): at most 0.09 m and
  // 0.007 rad; on the realistic preset (1076 edges) heading 0.10 deg at the 99th percentile,
  // roll and pitch 0.38 / 0.56 deg (single ones beyond 0.8).
  bool scan_to_scan_edges = true;
  double snap_min_t = 0.15;    // [m]
  double snap_min_r = 0.01;    // [rad]
  double loop_sigma_t = 0.1;   // [m]
  double loop_sigma_r = 0.01;  // [rad]
  // A verified closure must also agree with the graph: the optimized graph with it may cost at
  // most this much more (sum of squared Mahalanobis errors; chi-square of 6 dof: 22.5 at
  // p = 0.999) than without it.
  double max_closure_chi2 = 30.0;
  // The first keyframe of a robot after the first is held where it joined until a closure ties
  // it to the map: a gauge, not a measurement. A merged own-frame robot's first kept keyframe
  // carries the drift of its whole own-frame stretch, and the odometry edges near the map's
  // anchor are soft, so any real weight here turns the whole map towards that error (1 m /
  // 0.05 rad had turned a full KITTI-00-shaped drive's map by 0.46 deg, 3 m at 400 m).
  double joined_prior_sigma_t = 1000.0;  // [m]
  double joined_prior_sigma_r = 3.0;     // [rad]
  // Gravity reference (docs/consistency.md "Gravity reference"): a keyframe whose INTEGRATE
  // carried the robot's up direction gets a prior tying its attitude to the map's up direction
  // (the one measurement of a tilt of the whole map), with the sigma it was sent with but at
  // least gravity_sigma_floor, so that an overconfident source cannot outweigh the closures and
  // the odometry (its chi-square grows as 1 / sigma^2).
  bool gravity_priors = true;
  double gravity_sigma_floor = 0.0002;  // [rad] (0.011 deg)
};

}  // namespace socc::consistency
