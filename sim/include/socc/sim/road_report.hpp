#pragma once
// How well a route's heights fit the road its recorded attitude drove, before and after
// fuseRoadHeights: the figures of docs/simulator.md "Road heights" (socc-sim --road-report).
#include <cstddef>

#include "socc/kitti_io.hpp"
#include "socc/sim/road_heights.hpp"

namespace socc::sim {

struct RoadFit {
  // [rad] RMS over 10 m of road (windows every metre) of the attitude's grade minus the heights'
  // grade, their mean (the sensor's pitch against the road) taken out.
  double grade_rms = 0.0;
  double steepest = 0.0;       // the largest |grade| of the heights over 10 m
  double worst_revisit = 0.0;  // [m] the largest height difference of two passes of one place
};

/// poses' heights against their attitude. Two passes of one place: poses within revisit_radius
/// horizontally and min_path of driving apart.
RoadFit roadFit(const Poses& poses, double revisit_radius = 2.0, double min_path = 50.0);

struct RoadReport {
  RoadFit recorded;
  RoadFit road;
  RoadHeights heights;
};

RoadReport roadReport(const Poses& recorded, const RoadHeightModel& model = {});

}  // namespace socc::sim
