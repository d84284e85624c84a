#include "socc/sim/realism.hpp"

#include <algorithm>
#include <stdexcept>

namespace socc::sim {

bool Realism::anyScanError() const {
  const ReturnErrors& r = returns;
  return beams.any() || r.noise_per_metre > 0 || r.incidence_noise_gain > 0 ||
         r.detection_threshold > 0 || r.range_walk > 0 || r.dark_fraction > 0 ||
         r.glass_fraction > 0 || r.mixed_pixel_probability > 0 || r.beam_divergence_mrad > 0 ||
         r.foliage_depth > 0 || r.foliage_dropout > 0 || terrain.road_roughness > 0 ||
         terrain.terrain_roughness > 0 || labels.boundary_probability > 0 ||
         labels.confusion_probability > 0 || labels.single_scan_classes;
}

// The figures and their sources are in sim/README.md ("Realism").
Realism realismPreset(const std::string& name) {
  Realism r;
  r.name = name;
  if (name == "none") return r;
  if (name != "kitti") throw std::invalid_argument("unknown realism '" + name + "' (none, kitti)");
  r.beams = {0.08, 0.22, 0.05, 0.02, 0.002};
  r.returns.noise_per_metre = 2e-4;
  r.returns.incidence_noise_gain = 0.5;
  r.returns.detection_threshold = 4.5e-5;
  r.returns.range_walk = 0.05;
  r.returns.dark_fraction = 0.15;
  r.returns.glass_fraction = 0.3;
  r.returns.mixed_pixel_probability = 0.5;
  r.returns.beam_divergence_mrad = 2.0;
  r.returns.foliage_depth = 0.3;
  r.returns.foliage_dropout = 0.3;
  r.terrain = {0.02, 0.05};
  r.motion = {0.15, 0.35, 0.15, 0.1, 0.01, 0.02};
  r.labels = {0.6, 0.22, true};
  return r;
}

namespace {

// Single models inside a group, for ablations (which error drives a peer's drift).
bool disableModel(Realism& r, const std::string& name) {
  ReturnErrors& e = r.returns;
  if (name == "elevation_bias") {
    r.beams.elevation_bias_deg = 0.0;
  } else if (name == "beam_angles") {
    r.beams.elevation_sigma_deg = r.beams.azimuth_sigma_deg = 0.0;
  } else if (name == "beam_elevations") {
    r.beams.elevation_sigma_deg = 0.0;
  } else if (name == "beam_azimuths") {
    r.beams.azimuth_sigma_deg = 0.0;
  } else if (name == "beam_ranges") {
    r.beams.range_offset_sigma = r.beams.range_scale_sigma = 0.0;
  } else if (name == "range_offsets") {
    r.beams.range_offset_sigma = 0.0;
  } else if (name == "range_scales") {
    r.beams.range_scale_sigma = 0.0;
  } else if (name == "range_noise") {
    e.noise_per_metre = e.incidence_noise_gain = 0.0;
  } else if (name == "range_walk") {
    e.range_walk = 0.0;
  } else if (name == "edges") {
    e.beam_divergence_mrad = e.mixed_pixel_probability = 0.0;
  } else if (name == "surfaces") {
    e.dark_fraction = e.glass_fraction = e.foliage_depth = e.foliage_dropout = 0.0;
  } else if (name == "dark") {
    e.dark_fraction = 0.0;
  } else if (name == "glass") {
    e.glass_fraction = 0.0;
  } else if (name == "foliage") {
    e.foliage_depth = e.foliage_dropout = 0.0;
  } else if (name == "body") {
    const double vibration = r.motion.vibration_deg;
    r.motion = {};
    r.motion.vibration_deg = vibration;
  } else {
    return false;
  }
  return true;
}

}  // namespace

void disableRealism(Realism& r, const std::vector<std::string>& groups) {
  for (const auto& g : groups) {
    if (g == "beams") {
      r.beams = {};
    } else if (g == "returns") {
      r.returns = {};
    } else if (g == "terrain") {
      r.terrain = {};
    } else if (g == "motion") {
      r.motion = {};
    } else if (g == "labels") {
      r.labels = {};
    } else if (!disableModel(r, g)) {
      throw std::invalid_argument("unknown realism group '" + g + "' (" + kRealismSwitches + ")");
    }
  }
}

void scaleRealism(Realism& r, double f) {
  for (double* v :
       {&r.beams.elevation_sigma_deg, &r.beams.elevation_bias_deg, &r.beams.azimuth_sigma_deg,
        &r.beams.range_offset_sigma, &r.beams.range_scale_sigma, &r.returns.noise_per_metre,
        &r.returns.incidence_noise_gain, &r.returns.range_walk, &r.returns.beam_divergence_mrad,
        &r.returns.foliage_depth, &r.terrain.road_roughness, &r.terrain.terrain_roughness,
        &r.motion.pitch_per_acceleration_deg, &r.motion.roll_per_lateral_deg,
        &r.motion.bump_pitch_deg, &r.motion.bump_roll_deg, &r.motion.bump_heave,
        &r.motion.vibration_deg})
    *v *= f;
  // Probabilities saturate at 1.
  for (double* p : {&r.returns.dark_fraction, &r.returns.glass_fraction,
                    &r.returns.mixed_pixel_probability, &r.returns.foliage_dropout,
                    &r.labels.boundary_probability, &r.labels.confusion_probability})
    *p = std::min(1.0, *p * f);
}

}  // namespace socc::sim
