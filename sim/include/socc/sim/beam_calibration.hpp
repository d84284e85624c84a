#pragma once
// The intrinsic calibration error of one sensor instance: each laser's true elevation, azimuth,
// range offset and range scale differ from the nominal ones the points are computed with. Drawn
// once from the seed, so a sensor keeps its errors over the whole sequence.
#include <cstdint>
#include <vector>

#include "socc/sim/realism.hpp"

namespace socc::sim {

struct BeamCalibration {
  std::vector<double> elevation_error;  // [rad] true minus nominal, per laser
  std::vector<double> azimuth_error;    // [rad]
  std::vector<double> range_offset;     // [m] reported minus true range at 0 m
  std::vector<double> range_scale;      // reported = true * (1 + scale) + offset
};

BeamCalibration drawBeamCalibration(const BeamErrors& errors, std::size_t beams,
                                    std::uint64_t seed);

}  // namespace socc::sim
