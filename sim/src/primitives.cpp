#include "socc/sim/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace socc::sim {

namespace {

// Slab test against an axis-aligned box centred at the origin.
std::optional<double> intersectCenteredBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                           const Eigen::Vector3d& half) {
  double t_near = -kInf;
  double t_far = kInf;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (std::abs(o[i]) > half[i]) return std::nullopt;
      continue;
    }
    double t0 = (-half[i] - o[i]) / d[i];
    double t1 = (half[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return std::nullopt;
  }
  if (t_near <= kMinHitDistance) return std::nullopt;  // behind, or starting inside
  return t_near;
}

std::optional<double> intersectBox(const Ray& ray, const Box& b) {
  return intersectCenteredBox(toBoxFrame(b, ray.origin - b.center), toBoxFrame(b, ray.direction),
                              b.half_extents);
}

std::optional<double> intersectCylinder(const Ray& ray, const Cylinder& c) {
  const Eigen::Vector3d& o = ray.origin;
  const Eigen::Vector3d& d = ray.direction;
  double best = kInf;
  // Side: |o_xy + t d_xy - axis|^2 = r^2.
  const Eigen::Vector2d rel = o.head<2>() - c.axis_xy;
  const double a = d.head<2>().squaredNorm();
  if (a > 1e-12) {
    const double b = rel.dot(d.head<2>());
    const double disc = b * b - a * (rel.squaredNorm() - c.radius * c.radius);
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / a;  // entering root
      const double z = o.z() + t * d.z();
      if (t > kMinHitDistance && z >= c.z_min && z <= c.z_max) best = t;
    }
  }
  // Caps.
  if (std::abs(d.z()) > 1e-12) {
    for (const double zc : {c.z_min, c.z_max}) {
      const double t = (zc - o.z()) / d.z();
      if (t > kMinHitDistance && t < best &&
          (rel + t * d.head<2>()).squaredNorm() <= c.radius * c.radius)
        best = t;
    }
  }
  if (best == kInf) return std::nullopt;
  return best;
}

std::optional<double> intersectSphere(const Ray& ray, const Sphere& s) {
  const Eigen::Vector3d rel = ray.origin - s.center;
  const double b = rel.dot(ray.direction);
  const double disc = b * b - (rel.squaredNorm() - s.radius * s.radius);
  if (disc < 0.0) return std::nullopt;
  const double t = -b - std::sqrt(disc);
  if (t <= kMinHitDistance) return std::nullopt;
  return t;
}

}  // namespace

Box makeBox(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw, double pitch) {
  return Box{center, 0.5 * size, std::cos(yaw), std::sin(yaw), std::cos(pitch), std::sin(pitch)};
}

Eigen::Vector3d toBoxFrame(const Box& b, const Eigen::Vector3d& v) {
  // Undo the yaw about z, then the pitch about the box's y axis.
  const double x = b.cos_yaw * v.x() + b.sin_yaw * v.y();
  const double y = -b.sin_yaw * v.x() + b.cos_yaw * v.y();
  return {b.cos_pitch * x + b.sin_pitch * v.z(), y, -b.sin_pitch * x + b.cos_pitch * v.z()};
}

std::optional<double> intersect(const Ray& ray, const Shape& shape) {
  if (const auto* b = std::get_if<Box>(&shape)) return intersectBox(ray, *b);
  if (const auto* c = std::get_if<Cylinder>(&shape)) return intersectCylinder(ray, *c);
  return intersectSphere(ray, std::get<Sphere>(shape));
}

std::optional<double> intersect(const Ray& ray, const Plane& plane) {
  const double denom = plane.normal.dot(ray.direction);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double t = (plane.offset - plane.normal.dot(ray.origin)) / denom;
  if (t <= kMinHitDistance) return std::nullopt;
  return t;
}

Eigen::AlignedBox3d boundingBox(const Shape& shape) {
  if (const auto* b = std::get_if<Box>(&shape)) {
    // Pitched: the box's length and height mix in the vertical plane along its x axis.
    const Eigen::Vector3d& e = b->half_extents;
    const double length = std::abs(b->cos_pitch) * e.x() + std::abs(b->sin_pitch) * e.z();
    const double height = std::abs(b->sin_pitch) * e.x() + std::abs(b->cos_pitch) * e.z();
    const double hx = std::abs(b->cos_yaw) * length + std::abs(b->sin_yaw) * e.y();
    const double hy = std::abs(b->sin_yaw) * length + std::abs(b->cos_yaw) * e.y();
    const Eigen::Vector3d h(hx, hy, height);
    return {b->center - h, b->center + h};
  }
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    return {Eigen::Vector3d(c->axis_xy.x() - c->radius, c->axis_xy.y() - c->radius, c->z_min),
            Eigen::Vector3d(c->axis_xy.x() + c->radius, c->axis_xy.y() + c->radius, c->z_max)};
  }
  const auto& s = std::get<Sphere>(shape);
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(s.radius);
  return {s.center - r, s.center + r};
}

}  // namespace socc::sim
