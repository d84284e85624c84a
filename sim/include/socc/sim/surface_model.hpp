#pragma once
// World-fixed surface properties the analytic primitives do not carry: reflectivity (per class,
// with dark patches), windows in facades, and the unevenness of the ground. Each is a function
// of the world position and the world seed, so every scan sees the same surface.
#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "socc/sim/realism.hpp"

namespace socc::sim {

/// The albedo at 905 nm of the exact (error-free) model: one value per class.
float classAlbedo(std::uint16_t label);

class SurfaceModel {
 public:
  SurfaceModel(const ReturnErrors& returns, const TerrainErrors& terrain, std::uint64_t seed);

  /// Albedo of `label` at world point p: the class's, or 0.05 on a dark patch.
  float albedo(std::uint16_t label, const Eigen::Vector3d& p) const;
  /// Whether p of a facade lies in a window (glass).
  bool isGlass(std::uint16_t label, const Eigen::Vector3d& p) const;
  /// Height [m] of the real ground above the primitive's flat surface at p (0 off the ground).
  double groundHeight(std::uint16_t label, const Eigen::Vector3d& p) const;
  /// A key of the 2 m patch holding p (for effects that come in blobs).
  std::uint64_t patch(const Eigen::Vector3d& p, double size, std::uint64_t salt) const;

 private:
  ReturnErrors returns_;
  TerrainErrors terrain_;
  std::uint64_t seed_;
  struct Wave {
    Eigen::Vector2d k;  // [rad/m]
    double phase;
    double weight;
  };
  std::array<Wave, 4> waves_{};
};

bool isGroundLabel(std::uint16_t label);

}  // namespace socc::sim
