#pragma once
// Analytic world primitives and their exact ray intersections. Every primitive carries a raw
// SemanticKITTI label id (e.g. 10 car, 40 road, 50 building, 252 moving car).
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <optional>
#include <variant>

namespace socc::sim {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  // unit length
};

/// A box rotated by yaw about the vertical axis (streets follow curved paths) and then pitched
/// about its own y axis (road tiles follow the street's grade: its x axis rises at `pitch`).
struct Box {
  Eigen::Vector3d center;
  Eigen::Vector3d half_extents;  // along the box's own x (length), y (width), z (height)
  double cos_yaw = 1.0;
  double sin_yaw = 0.0;
  double cos_pitch = 1.0;
  double sin_pitch = 0.0;
};
Box makeBox(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw = 0.0,
            double pitch = 0.0);

/// A world-frame vector in the box's own axes (rotation only).
Eigen::Vector3d toBoxFrame(const Box& box, const Eigen::Vector3d& v);

/// A vertical cylinder with flat caps (poles, trunks, pillars, people).
struct Cylinder {
  Eigen::Vector2d axis_xy;
  double z_min = 0.0;
  double z_max = 0.0;
  double radius = 0.0;
};

struct Sphere {
  Eigen::Vector3d center;
  double radius = 0.0;
};

using Shape = std::variant<Box, Cylinder, Sphere>;

struct Primitive {
  Shape shape;
  std::uint16_t label = 0;  // raw SemanticKITTI id
};

/// Infinite plane n . x = offset (floors and ceilings); kept out of the acceleration grid.
struct Plane {
  Eigen::Vector3d normal;
  double offset = 0.0;
  std::uint16_t label = 0;
};

/// Distance along the ray to the nearest surface point with t > kMinHitDistance, if any. A ray
/// starting inside a solid does not hit it (the sensor is never inside an object).
std::optional<double> intersect(const Ray& ray, const Shape& shape);
std::optional<double> intersect(const Ray& ray, const Plane& plane);

Eigen::AlignedBox3d boundingBox(const Shape& shape);

inline constexpr double kMinHitDistance = 1e-6;

}  // namespace socc::sim
