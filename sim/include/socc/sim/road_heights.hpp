#pragma once
// The road's heights under a recorded route. KITTI's ground truth (an OxTS GPS/INS) has an
// attitude far better than its GPS heights: where a drive comes back to a place, its passes are
// recorded up to 6 m apart (00: 1.1 m, 02: 4.4 m, 08: 6.4 m, 09: 3.2 m), and KITTI 08's heights
// climb 16 m within its first 45 m while its pitch says the road is level (docs/simulator.md
// "Road heights"). A world built at those heights has two road slabs at a revisit and ramps
// under a level car, places no real drive comes to. fuseRoadHeights gives the road that the
// recorded attitude drove (its grade follows the vehicle's pitch over short distances, but for
// the sensor's constant pitch against the road, estimated: 0.5-1.0 deg on KITTI), the GPS
// heights over long ones (beyond gps_sigma / grade_sigma metres: an attitude's grade error
// integrates into height drift) and one height at every revisit, as a pose graph spreads a
// loop's error. Only heights change: the attitude stays as recorded.
#include <cstddef>
#include <vector>

#include "socc/kitti_io.hpp"

namespace socc::sim {

struct RoadHeightModel {
  double radius = 4.0;          // [m] horizontally: two passes of one place (lanes apart)
  double min_path = 50.0;       // [m] of drive between two passes of one place
  double revisit_sigma = 0.02;  // [m] how closely the passes must agree
  // The road's grade against the vehicle's pitch (suspension pitch with braking and load,
  // about +-0.5 deg, and the sensor's mounting), over each metre of road.
  double grade_sigma = 0.005;
  double pitch_sigma = 0.035;  // the sensor's constant pitch against the road (a prior, 2 deg)
  double gps_sigma = 1.5;      // [m] the recorded heights' error, over each metre of road
  double bend_sigma = 0.001;   // [1/m] how fast the road's grade may change
};

struct RoadHeights {
  Poses poses;
  std::vector<double> change;     // [m] per pose: its height minus the recorded one
  std::size_t revisit_pairs = 0;  // poses tied to an earlier pass
  double max_change = 0.0;        // [m] the largest |change|
  double sensor_pitch = 0.0;      // [rad] the sensor's pitch against the road (+: nose up)
};

/// poses (sensor poses, +z up) at the heights of the road they drove; the first pose keeps its
/// height. Revisits at any angle are tied (a route over a bridge across its own earlier path
/// needs its recorded heights).
RoadHeights fuseRoadHeights(const Poses& poses, const RoadHeightModel& model = {});

}  // namespace socc::sim
