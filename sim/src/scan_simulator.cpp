#include "socc/sim/scan_simulator.hpp"

#include <tbb/parallel_for.h>

#include <cmath>

#include "realistic_scan.hpp"
#include "socc/sim/random.hpp"
#include "socc/sim/surface_model.hpp"

namespace socc::sim {

namespace {

struct RayResult {
  Eigen::Vector3f point;
  std::uint16_t label = 0;
  bool valid = false;
};

}  // namespace

SimulatedScan simulateScan(const Scene& scene, const LidarModel& model, double sweep_start,
                           std::uint64_t frame, const ScanOptions& options) {
  if (options.realism && options.realism->anyScanError())
    return simulateRealisticScan(scene, model, sweep_start, frame, options);
  const WorldSnapshot world = scene.world.at(sweep_start);
  const int beams = static_cast<int>(model.elevations_deg.size());
  std::vector<Eigen::Vector3d> beam_dirs;  // at azimuth 0
  for (const double e : model.elevations_deg) {
    const double r = e * M_PI / 180.0;
    beam_dirs.emplace_back(std::cos(r), 0.0, std::sin(r));
  }
  const Eigen::Isometry3d start_pose = scene.trajectory.poseAt(sweep_start);
  std::vector<RayResult> rays(static_cast<std::size_t>(model.columns) * beam_dirs.size());

  tbb::parallel_for(0, model.columns, [&](int c) {
    const double tau = model.columnTime(c);
    const Eigen::Isometry3d pose =
        options.motion_distortion ? scene.trajectory.poseAt(sweep_start + tau) : start_pose;
    const Eigen::AngleAxisd azimuth(model.columnAzimuth(c), Eigen::Vector3d::UnitZ());
    for (int b = 0; b < beams; ++b) {
      const std::size_t index = static_cast<std::size_t>(c) * beam_dirs.size() + b;
      const Eigen::Vector3d local = azimuth * beam_dirs[static_cast<std::size_t>(b)];
      const Ray ray{pose.translation(), pose.linear() * local};
      const auto hit = world.cast(ray, model.max_range);
      if (!hit || hit->range < model.min_range) continue;
      const RayDraw draw = rayDraw(options.seed, frame, index);
      if (draw.u3 < model.dropout) continue;
      const double range = hit->range + model.range_noise * draw.gaussian();
      if (range < model.min_range || range > model.max_range) continue;
      rays[index] = {(range * local).cast<float>(), hit->label, true};
    }
  });

  SimulatedScan scan;
  scan.points.reserve(rays.size());
  scan.labels.reserve(rays.size());
  scan.times.reserve(rays.size());
  scan.reflectance.reserve(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!rays[i].valid) continue;
    scan.points.push_back(rays[i].point);
    scan.labels.push_back(rays[i].label);
    scan.times.push_back(
        static_cast<float>(model.columnTime(static_cast<int>(i / beam_dirs.size()))));
    scan.reflectance.push_back(classAlbedo(rays[i].label));
  }
  return scan;
}

}  // namespace socc::sim
