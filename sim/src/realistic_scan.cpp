#include "realistic_scan.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include "socc/sim/beam_calibration.hpp"
#include "socc/sim/label_noise.hpp"
#include "socc/sim/random.hpp"
#include "socc/sim/room_model.hpp"
#include "socc/sim/semantic_ids.hpp"
#include "socc/sim/surface_model.hpp"

namespace socc::sim {

namespace {

// Salts of the per-ray random streams (each effect draws independently of the others).
constexpr std::uint64_t kSurfaceStream = 0x5A17;
constexpr std::uint64_t kReturnStream = 0x5A18;
constexpr std::uint64_t kEdgeStream = 0x5A19;
constexpr std::uint64_t kLabelStream = 0x5A1A;
// The rooms behind windows (room_model.hpp; sizes and sources in sim/README.md "Realism").
constexpr RoomLayout kRooms{};

// What the beam physically met (pass 1), before the receiver's errors.
struct Return {
  float true_range = 0.0f;  // geometric range along the true beam (for neighbours' geometry)
  float range = 0.0f;       // range the pulse travelled (foliage or a room's depth added)
  float albedo = 0.0f;
  std::uint16_t label = 0;
  bool valid = false;
  std::uint64_t patch = 0;  // 2 m world patch (label-error blobs)
  bool echo = true;         // false: a window reflected the pulse away (geometry still known)
};

class RangeImage {
 public:
  RangeImage(int columns, int beams)
      : columns_(columns),
        beams_(beams),
        cells_(static_cast<std::size_t>(columns) * static_cast<std::size_t>(beams)) {}
  std::size_t index(int c, int b) const {
    return static_cast<std::size_t>(c) * static_cast<std::size_t>(beams_) +
           static_cast<std::size_t>(b);
  }
  Return& at(int c, int b) { return cells_[index(c, b)]; }
  // Neighbours wrap around in azimuth and stop at the top and bottom beams.
  const Return* neighbour(int c, int b) const {
    if (b < 0 || b >= beams_) return nullptr;
    const int cw = (c + columns_) % columns_;
    const Return& r = cells_[index(cw, b)];
    return r.valid ? &r : nullptr;
  }
  int columns() const { return columns_; }
  int beams() const { return beams_; }

 private:
  int columns_;
  int beams_;
  std::vector<Return> cells_;
};

Eigen::Vector3d beamDirection(double elevation, double azimuth) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
          std::sin(elevation)};
}

// Cosine of the incidence angle at (c, b) from its neighbours' points (1 when unknown).
double incidenceCosine(const RangeImage& image, const std::vector<Eigen::Vector3d>& dirs, int c,
                       int b, double range) {
  const auto point = [&](int cc, int bb) -> std::optional<Eigen::Vector3d> {
    const Return* r = image.neighbour(cc, bb);
    if (!r || std::abs(r->true_range - range) > 0.1 * range + 0.3) return std::nullopt;
    const int cw = (cc + image.columns()) % image.columns();
    return r->true_range * dirs[image.index(cw, bb)];
  };
  const Eigen::Vector3d here = range * dirs[image.index(c, b)];
  const auto tangent = [&](std::optional<Eigen::Vector3d> a,
                           std::optional<Eigen::Vector3d> z) -> std::optional<Eigen::Vector3d> {
    if (a && z) return *z - *a;
    if (a) return here - *a;
    if (z) return *z - here;
    return std::nullopt;
  };
  const auto t1 = tangent(point(c - 1, b), point(c + 1, b));
  const auto t2 = tangent(point(c, b - 1), point(c, b + 1));
  if (!t1 || !t2) return 1.0;
  const Eigen::Vector3d n = t1->cross(*t2);
  const double norm = n.norm();
  if (norm < 1e-12) return 1.0;
  return std::abs(n.dot(here)) / (norm * range);
}

// Pass 1: cast the true (miscalibrated) beams into the world.
void castBeams(const Scene& scene, const LidarModel& model, double sweep_start, std::uint64_t frame,
               const ScanOptions& options, const BeamCalibration& calib,
               const SurfaceModel& surface, RangeImage& image) {
  const WorldSnapshot world = scene.world.at(sweep_start);
  const Realism& real = *options.realism;
  const Eigen::Isometry3d start_pose = scene.trajectory.poseAt(sweep_start);
  const int beams = image.beams();
  tbb::parallel_for(0, model.columns, [&](int c) {
    const double tau = model.columnTime(c);
    const Eigen::Isometry3d pose =
        options.motion_distortion ? scene.trajectory.poseAt(sweep_start + tau) : start_pose;
    for (int b = 0; b < beams; ++b) {
      const auto bi = static_cast<std::size_t>(b);
      const double elevation = model.elevations_deg[bi] * M_PI / 180.0 + calib.elevation_error[bi];
      const Eigen::Vector3d local =
          beamDirection(elevation, model.columnAzimuth(c) + calib.azimuth_error[bi]);
      const Ray ray{pose.translation(), pose.linear() * local};
      const auto hit = world.cast(ray, model.max_range + 10.0);
      if (!hit) continue;
      double range = hit->range;
      Eigen::Vector3d p = ray.origin + range * ray.direction;
      // Uneven ground: intersect the raised surface to first order along the ray.
      const double h = surface.groundHeight(hit->label, p);
      if (h != 0.0 && ray.direction.z() < -0.02) {
        range += h / ray.direction.z();
        p = ray.origin + range * ray.direction;
      }
      if (range < model.min_range) continue;
      const RayDraw draw = rayDraw(options.seed ^ kSurfaceStream, frame, image.index(c, b));
      double travelled = range;
      const ReturnErrors& e = real.returns;
      if (hit->label == raw::kVegetation && (e.foliage_depth > 0 || e.foliage_dropout > 0)) {
        // Foliage: the pulse passes through gaps or returns from leaves deeper inside.
        if (draw.u1 < e.foliage_dropout) continue;
        travelled += -e.foliage_depth * std::log(1.0 - draw.u2);
      }
      // A window: no return (specular) or one from the room behind it. The geometry of the
      // facade beside it is still known (pass 2 takes neighbours' surfaces from it).
      bool echo = true;
      if (surface.isGlass(hit->label, p)) {
        const Box* building = hit->shape ? std::get_if<Box>(hit->shape) : nullptr;
        const std::optional<double> inside =
            building && draw.u1 >= 0.5 ? roomTravel(ray, range, *building, kRooms) : std::nullopt;
        echo = inside.has_value();
        if (inside) travelled += *inside;
      }
      image.at(c, b) = {static_cast<float>(range),
                        static_cast<float>(travelled),
                        surface.albedo(hit->label, p),
                        hit->label,
                        true,
                        surface.patch(p, 2.0, 0x1AB3),
                        echo};
    }
  });
}

struct Measured {
  Eigen::Vector3f point;
  float reflectance = 0.0f;
  std::uint16_t label = 0;
  bool valid = false;
};

// Pass 2: what the receiver reports for each return.
void measure(const LidarModel& model, std::uint64_t frame, const ScanOptions& options,
             const BeamCalibration& calib, const RangeImage& image,
             const std::vector<Eigen::Vector3d>& dirs, std::vector<Measured>& out) {
  const ReturnErrors& e = options.realism->returns;
  const double column_step = 2.0 * M_PI / model.columns;  // [rad]
  // Share of edge pixels whose footprint (half the divergence each side) reaches across.
  const double straddle = std::min(1.0, 0.5e-3 * e.beam_divergence_mrad / column_step);
  tbb::parallel_for(0, image.columns(), [&](int c) {
    for (int b = 0; b < image.beams(); ++b) {
      const std::size_t i = image.index(c, b);
      const Return* r = image.neighbour(c, b);
      if (!r || !r->echo) continue;
      const RayDraw d = rayDraw(options.seed ^ kReturnStream, frame, i);
      const RayDraw edge = rayDraw(options.seed ^ kEdgeStream, frame, i);
      if (d.u3 < model.dropout) continue;
      double range = r->range;
      const double cosine = incidenceCosine(image, dirs, c, b, r->true_range);
      // Detection: the signal falls with albedo, incidence and range squared.
      double walk = 0.0;
      if (e.detection_threshold > 0.0) {
        const double signal = r->albedo * std::sqrt(std::max(cosine, 0.01)) / (range * range);
        const double ratio = signal / e.detection_threshold;
        if (edge.u3 < 1.0 / (1.0 + ratio * ratio * ratio)) continue;
        walk = e.range_walk * std::clamp(1.0 - std::log10(ratio) / 2.0, 0.0, 1.0);
      }
      // Depth edges: the footprint covers both surfaces. A far pixel next to a near one returns
      // the near surface (edges bloat); close surfaces blend into a mixed pixel between them.
      if (straddle > 0.0 && edge.u1 < straddle) {
        const Return* n = image.neighbour(edge.u2 < 0.5 ? c - 1 : c + 1, b);
        if (n && std::abs(n->true_range - r->true_range) > std::max(0.3, 0.02 * range)) {
          if (std::abs(n->true_range - r->true_range) < 5.0 &&
              edge.u2 * 2.0 - std::floor(edge.u2 * 2.0) < e.mixed_pixel_probability)
            range += (n->true_range - r->true_range) * d.u1;
          else if (n->true_range < r->true_range)
            range = n->true_range;
        }
      }
      const double tangent =
          std::sqrt(std::max(0.0, 1.0 - cosine * cosine)) / std::max(cosine, 0.2);
      const double sigma = (model.range_noise + e.noise_per_metre * range) *
                           (1.0 + e.incidence_noise_gain * std::min(tangent, 5.0));
      range += sigma * d.gaussian() + walk;
      range = range * (1.0 + calib.range_scale[static_cast<std::size_t>(b)]) +
              calib.range_offset[static_cast<std::size_t>(b)];
      if (range < model.min_range || range > model.max_range) continue;
      out[i] = {(range * dirs[i]).cast<float>(), r->albedo, r->label, true};
    }
  });
}

// Pass 3: the labels a network would give (boundary bleeding, confused blobs, no movers).
std::uint16_t networkLabel(const RangeImage& image, const std::vector<Measured>& out,
                           const LabelErrors& e, std::uint64_t seed, std::uint64_t frame, int c,
                           int b) {
  const std::size_t i = image.index(c, b);
  std::uint16_t label = out[i].label;
  if (e.single_scan_classes) label = singleScanRawId(label);
  const RayDraw d = rayDraw(seed ^ kLabelStream, frame, i);
  if (e.boundary_probability > 0.0 && d.u1 < e.boundary_probability) {
    const int pick = static_cast<int>(d.u2 * 4.0);
    const int dc[4] = {-1, 1, 0, 0};
    const int db[4] = {0, 0, -1, 1};
    const int nb = b + db[pick];
    if (nb >= 0 && nb < image.beams()) {
      const std::size_t j = image.index((c + dc[pick] + image.columns()) % image.columns(), nb);
      if (out[j].valid)
        label = e.single_scan_classes ? singleScanRawId(out[j].label) : out[j].label;
    }
  }
  if (e.confusion_probability > 0.0) {
    // Blobs: one draw per 2 m patch and scan, so neighbouring points err together.
    const std::uint64_t blob = splitMix64(image.neighbour(c, b)->patch ^ (frame * 0x9E37u));
    if (toUnit(blob) < e.confusion_probability) {
      const std::uint8_t cls = mapSemanticKittiLabel(label);
      const std::uint8_t other = confusedClass(cls, toUnit(splitMix64(blob)) < 0.3);
      if (other != cls) label = semanticKittiRawId(other);
    }
  }
  return label;
}

}  // namespace

SimulatedScan simulateRealisticScan(const Scene& scene, const LidarModel& model, double sweep_start,
                                    std::uint64_t frame, const ScanOptions& options) {
  const Realism& real = *options.realism;
  const int beams = static_cast<int>(model.elevations_deg.size());
  // The sensor instance (calibration) depends on its seed only, the world's surfaces on the seed.
  const BeamCalibration calib = drawBeamCalibration(real.beams, model.elevations_deg.size(),
                                                    options.sensor_seed.value_or(options.seed));
  // Windows open into rooms the sensor never enters: a model of exterior walls. Indoors a room
  // behind a wall would stand in the sensor's own free space (phantom walls in its corridors).
  ReturnErrors returns = real.returns;
  if (!scene.exterior_walls) returns.glass_fraction = 0.0;
  const SurfaceModel surface(returns, real.terrain, options.seed);
  RangeImage image(model.columns, beams);
  castBeams(scene, model, sweep_start, frame, options, calib, surface, image);

  // Nominal directions: what the sensor believes each beam looked along.
  std::vector<Eigen::Vector3d> dirs(static_cast<std::size_t>(model.columns) *
                                    static_cast<std::size_t>(beams));
  for (int c = 0; c < model.columns; ++c)
    for (int b = 0; b < beams; ++b)
      dirs[image.index(c, b)] = beamDirection(
          model.elevations_deg[static_cast<std::size_t>(b)] * M_PI / 180.0, model.columnAzimuth(c));
  std::vector<Measured> out(dirs.size());
  measure(model, frame, options, calib, image, dirs, out);

  SimulatedScan scan;
  scan.points.reserve(out.size());
  for (int c = 0; c < model.columns; ++c) {
    for (int b = 0; b < beams; ++b) {
      const Measured& m = out[image.index(c, b)];
      if (!m.valid) continue;
      scan.points.push_back(m.point);
      scan.exact_labels.push_back(m.label);
      scan.labels.push_back(networkLabel(image, out, real.labels, options.seed, frame, c, b));
      scan.times.push_back(static_cast<float>(model.columnTime(c)));
      scan.reflectance.push_back(m.reflectance);
    }
  }
  return scan;
}

}  // namespace socc::sim
