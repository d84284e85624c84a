#pragma once
// Error models that make simulated scans as hard as real ones (sim/README.md "Realism" lists
// every model with its real-world magnitude and the source of that figure). All magnitudes are
// zero in the "none" preset, which keeps the simulator exact and bit-identical to its output
// before these models existed.
#include <string>
#include <vector>

namespace socc::sim {

/// Intrinsic calibration errors of one sensor instance, drawn once per laser from the seed.
struct BeamErrors {
  double elevation_sigma_deg = 0.0;  // per-laser vertical-angle offset
  double elevation_bias_deg = 0.0;   // common vertical-angle offset (KITTI's HDL-64: ~0.2 deg)
  double azimuth_sigma_deg = 0.0;    // per-laser horizontal-angle offset
  double range_offset_sigma = 0.0;   // [m] per-laser range offset
  double range_scale_sigma = 0.0;    // per-laser relative range scale error

  bool any() const {
    return elevation_sigma_deg > 0 || elevation_bias_deg != 0 || azimuth_sigma_deg > 0 ||
           range_offset_sigma > 0 || range_scale_sigma > 0;
  }
};

/// How one return depends on range, incidence, reflectivity and what the beam hits.
struct ReturnErrors {
  double noise_per_metre = 0.0;       // range sigma grows by this many metres per metre of range
  double incidence_noise_gain = 0.0;  // sigma *= 1 + gain * min(tan(incidence), 5)
  double detection_threshold = 0.0;   // albedo * cos(incidence) / range^2 at 50 % detection
  double range_walk = 0.0;            // [m] range bias of a return at the detection threshold
  double dark_fraction = 0.0;         // share of surfaces (2 m patches) painted dark (albedo 0.05)
  double glass_fraction = 0.0;        // share of facade patches that are windows
  double mixed_pixel_probability = 0.0;  // a return at a depth edge lands between both surfaces
  double beam_divergence_mrad = 0.0;     // full angle; foreground edges bloat by half of it
  double foliage_depth = 0.0;            // [m] mean penetration into vegetation (exponential)
  double foliage_dropout = 0.0;          // probability a beam passes through foliage gaps
};

/// Surface shape the primitives do not have: a rough, uneven ground.
struct TerrainErrors {
  double road_roughness = 0.0;     // [m] height amplitude of road and sidewalk unevenness
  double terrain_roughness = 0.0;  // [m] of terrain (grass, soil)
};

/// The car body moving on its suspension, on top of the route's smooth pose.
struct MotionErrors {
  double pitch_per_acceleration_deg =
      0.0;                            // [deg per m/s^2] dive when braking, squat when accelerating
  double roll_per_lateral_deg = 0.0;  // [deg per m/s^2] roll in turns
  double bump_pitch_deg = 0.0;        // body pitch/roll/heave oscillation (1-2 Hz) amplitudes
  double bump_roll_deg = 0.0;
  double bump_heave = 0.0;     // [m]
  double vibration_deg = 0.0;  // wheel-hop / engine vibration (8-15 Hz) amplitude
};

/// Labels as a single-scan segmentation network gives them.
struct LabelErrors {
  double boundary_probability = 0.0;   // a point next to another class takes that class
  double confusion_probability = 0.0;  // a 2 m blob takes a commonly confused class
  bool single_scan_classes = false;    // no moving-object ids (a network sees one scan)
};

struct Realism {
  std::string name = "none";
  BeamErrors beams;
  ReturnErrors returns;
  TerrainErrors terrain;
  MotionErrors motion;
  LabelErrors labels;

  bool anyScanError() const;  // anything but motion changes the scans
};

/// "none" (exact) or "kitti" (a KITTI-like HDL-64 on a car). Throws std::invalid_argument.
Realism realismPreset(const std::string& name);

/// Names disableRealism accepts: the groups, then single models of a group (for ablations;
/// "body" is the motion group without its vibration).
inline constexpr const char* kRealismSwitches =
    "beams, returns, terrain, motion, labels; elevation_bias, beam_angles (beam_elevations, "
    "beam_azimuths), beam_ranges "
    "(range_offsets, range_scales), "
    "range_noise, range_walk, edges, surfaces (dark, glass, foliage), body";

/// Switches groups or single models off (kRealismSwitches).
/// Throws std::invalid_argument on an unknown name.
void disableRealism(Realism& realism, const std::vector<std::string>& groups);

/// Multiplies every magnitude (not the switches) by `factor` (for calibration).
void scaleRealism(Realism& realism, double factor);

}  // namespace socc::sim
