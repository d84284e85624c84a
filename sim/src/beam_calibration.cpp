#include "socc/sim/beam_calibration.hpp"

#include <cmath>

#include "socc/sim/random.hpp"

namespace socc::sim {

BeamCalibration drawBeamCalibration(const BeamErrors& e, std::size_t beams, std::uint64_t seed) {
  constexpr double kRadiansPerDegree = M_PI / 180.0;
  BeamCalibration c;
  for (std::size_t b = 0; b < beams; ++b) {
    const RayDraw angles = rayDraw(seed, 0xCA11B0, b);
    const RayDraw ranges = rayDraw(seed, 0xCA11B1, b);
    const RayDraw azimuth = rayDraw(seed, 0xCA11B2, b);
    c.elevation_error.push_back((e.elevation_bias_deg + e.elevation_sigma_deg * angles.gaussian()) *
                                kRadiansPerDegree);
    c.azimuth_error.push_back(e.azimuth_sigma_deg * azimuth.gaussian() * kRadiansPerDegree);
    c.range_offset.push_back(e.range_offset_sigma * ranges.gaussian());
    // A second gaussian from the same uniforms (sin instead of cos) is independent of the first.
    const double g2 =
        std::sqrt(-2.0 * std::log(1.0 - ranges.u1)) * std::sin(2.0 * M_PI * ranges.u2);
    c.range_scale.push_back(e.range_scale_sigma * g2);
  }
  return c;
}

}  // namespace socc::sim
