#include "socc/sim/surface_model.hpp"

#include <cmath>

#include "socc/sim/random.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

float classAlbedo(std::uint16_t label) {
  switch (label) {
    case raw::kRoad:
      return 0.15f;
    case raw::kSidewalk:
      return 0.3f;
    case raw::kVegetation:
    case raw::kTerrain:
      return 0.45f;
    case raw::kTrafficSign:
      return 0.95f;
    case raw::kCar:
    case raw::kMovingCar:
      return 0.6f;
    default:
      return 0.35f;
  }
}

bool isGroundLabel(std::uint16_t label) {
  return label == raw::kRoad || label == raw::kSidewalk || label == raw::kTerrain ||
         label == raw::kOtherGround;
}

SurfaceModel::SurfaceModel(const ReturnErrors& returns, const TerrainErrors& terrain,
                           std::uint64_t seed)
    : returns_(returns), terrain_(terrain), seed_(splitMix64(seed ^ 0x5EEDF00Du)) {
  // Unevenness: four plane waves at wavelengths 0.8-12 m, random directions; weights give a
  // unit peak amplitude (longer waves carry more of it, as road profiles do).
  Random rng(seed_);
  const double wavelengths[4] = {0.8, 2.1, 5.0, 12.0};
  const double weights[4] = {0.1, 0.2, 0.3, 0.4};
  for (int i = 0; i < 4; ++i) {
    const double a = rng.uniform(0, 2 * M_PI);
    waves_[static_cast<std::size_t>(i)] = {
        2 * M_PI / wavelengths[i] * Eigen::Vector2d(std::cos(a), std::sin(a)),
        rng.uniform(0, 2 * M_PI), weights[i]};
  }
}

std::uint64_t SurfaceModel::patch(const Eigen::Vector3d& p, double size, std::uint64_t salt) const {
  const auto cell = [&](double v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / size)));
  };
  std::uint64_t h = splitMix64(seed_ ^ salt);
  h = splitMix64(h ^ cell(p.x()));
  h = splitMix64(h ^ cell(p.y()));
  return splitMix64(h ^ cell(p.z()));
}

float SurfaceModel::albedo(std::uint16_t label, const Eigen::Vector3d& p) const {
  const float base = classAlbedo(label);
  if (returns_.dark_fraction <= 0.0 || isGroundLabel(label) || label == raw::kVegetation ||
      label == raw::kTrafficSign)
    return base;
  return toUnit(patch(p, 2.0, 0xDA4C)) < returns_.dark_fraction ? 0.05f : base;
}

bool SurfaceModel::isGlass(std::uint16_t label, const Eigen::Vector3d& p) const {
  return label == raw::kBuilding && returns_.glass_fraction > 0.0 &&
         toUnit(patch(p, 1.5, 0x61A55)) < returns_.glass_fraction;
}

double SurfaceModel::groundHeight(std::uint16_t label, const Eigen::Vector3d& p) const {
  if (!isGroundLabel(label)) return 0.0;
  const double amplitude =
      label == raw::kTerrain ? terrain_.terrain_roughness : terrain_.road_roughness;
  if (amplitude <= 0.0) return 0.0;
  double h = 0.0;
  for (const Wave& w : waves_) h += w.weight * std::sin(w.k.dot(p.head<2>()) + w.phase);
  return amplitude * h;
}

}  // namespace socc::sim
