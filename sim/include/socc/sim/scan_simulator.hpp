#pragma once
// Ray-casts one LiDAR sweep.
//
// Conventions (what deskewing code must undo):
//  - The sweep of frame k starts at t_k = k * frame_period; column c fires at
//    t_k + tau_c with tau_c = c / columns * sweep_period in [0, sweep_period).
//  - Without motion distortion every ray leaves from the pose at t_k and points are in that
//    sensor frame (an ideal, instantaneous scan).
//  - With motion distortion column c leaves from the pose at t_k + tau_c and its points are
//    expressed in THAT instantaneous sensor frame, as a real spinning LiDAR reports them; the
//    per-point time is tau_c. Deskewing maps point p with time tau to T(t_k)^-1 T(t_k + tau) p,
//    i.e. into the sensor frame at the sweep's reference time t_k (the pose in poses.txt).
//  - Movers are frozen at t_k during a sweep.
#include <cstdint>
#include <optional>
#include <vector>

#include "socc/point_cloud.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/realism.hpp"
#include "socc/sim/scene.hpp"

namespace socc::sim {

struct SimulatedScan {
  Points points;                            // sensor frame (see the conventions above)
  std::vector<std::uint32_t> labels;        // raw SemanticKITTI ids
  std::vector<float> times;                 // [s] within the sweep
  std::vector<float> reflectance;           // a per-class albedo in [0, 1]
  std::vector<std::uint32_t> exact_labels;  // with realism: the true labels (`labels` is noisy)
};

struct ScanOptions {
  bool motion_distortion = false;
  std::uint64_t seed = 1;  // noise and dropouts depend only on (seed, frame, ray)
  /// Error models (sim/README.md "Realism"); null or all off: the exact scan.
  const Realism* realism = nullptr;
  /// The sensor instance whose calibration errors (realism beams) the scan carries; unset: seed.
  /// Separate so that one sensor can drive through many worlds (KITTI used one HDL-64).
  std::optional<std::uint64_t> sensor_seed = std::nullopt;
};

SimulatedScan simulateScan(const Scene& scene, const LidarModel& model, double sweep_start,
                           std::uint64_t frame, const ScanOptions& options);

}  // namespace socc::sim
