// Ray-primitive intersections against hand-computed distances.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/sim/primitives.hpp"

namespace socc::sim {
namespace {

Ray ray(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  return {o, d.normalized()};
}

TEST(Primitives, Sphere) {
  const Sphere s{{10, 0, 0}, 2};
  EXPECT_NEAR(*intersect(ray({0, 0, 0}, {1, 0, 0}), s), 8.0, 1e-12);
  EXPECT_FALSE(intersect(ray({0, 0, 0}, {-1, 0, 0}), s));  // behind
  EXPECT_FALSE(intersect(ray({0, 0, 0}, {0, 1, 0}), s));
  EXPECT_FALSE(intersect(ray({10, 0, 0}, {1, 0, 0}), s));  // from inside
}

TEST(Primitives, RotatedBox) {
  // A 2 x 2 x 2 cube at (10, 0, 0) rotated 45 deg: its edge points at the sensor.
  const Box b = makeBox({10, 0, 0}, {2, 2, 2}, M_PI / 4);
  EXPECT_NEAR(*intersect(ray({0, 0, 0}, {1, 0, 0}), b), 10.0 - std::sqrt(2.0), 1e-12);
  const Box a = makeBox({10, 0, 0}, {2, 4, 6});
  EXPECT_NEAR(*intersect(ray({0, 0, 0}, {1, 0, 0}), a), 9.0, 1e-12);
  EXPECT_NEAR(*intersect(ray({10, 0, 10}, {0, 0, -1}), a), 7.0, 1e-12);
  EXPECT_FALSE(intersect(ray({0, 3, 0}, {1, 0, 0}), a));
}

TEST(Primitives, CylinderSideAndCaps) {
  const Cylinder c{Eigen::Vector2d(5, 0), 0.0, 3.0, 0.5};
  EXPECT_NEAR(*intersect(ray({0, 0, 1}, {1, 0, 0}), c), 4.5, 1e-12);
  EXPECT_NEAR(*intersect(ray({5, 0, 10}, {0, 0, -1}), c), 7.0, 1e-12);  // top cap
  EXPECT_FALSE(intersect(ray({0, 0, 4}, {1, 0, 0}), c));                // above
  // Slanted ray through the side at height 1.5.
  const Eigen::Vector3d d = Eigen::Vector3d(4.5, 0, 0.5).normalized();
  EXPECT_NEAR(*intersect(ray({0, 0, 1}, d), c), std::hypot(4.5, 0.5), 1e-12);
}

TEST(Primitives, Plane) {
  const Plane floor{Eigen::Vector3d::UnitZ(), -1.73, 40};
  const Eigen::Vector3d d = Eigen::Vector3d(1, 0, -1).normalized();
  EXPECT_NEAR(*intersect(ray({0, 0, 0}, d), floor), 1.73 * std::sqrt(2.0), 1e-12);
  EXPECT_FALSE(intersect(ray({0, 0, 0}, {1, 0, 0}), floor));
}

TEST(Primitives, BoundingBoxes) {
  const Eigen::AlignedBox3d b = boundingBox(makeBox({0, 0, 0}, {2, 2, 2}, M_PI / 4));
  EXPECT_NEAR(b.max().x(), std::sqrt(2.0), 1e-12);
  const Eigen::AlignedBox3d c = boundingBox(Cylinder{Eigen::Vector2d(1, 2), -1, 3, 0.5});
  EXPECT_TRUE(c.min().isApprox(Eigen::Vector3d(0.5, 1.5, -1)));
}

TEST(Primitives, PitchedBoxFollowsItsGrade) {
  // A 10 m slab 1 m thick rising 5 % along its yawed x axis (here the world's y).
  const double pitch = std::atan(0.05);
  const Box b = makeBox({0, 0, 0}, {10, 4, 1}, M_PI / 2, pitch);
  for (const double along : {-4.0, 0.0, 3.0}) {
    const Ray down{{0.0, along, 10.0}, {0, 0, -1}};
    const auto t = intersect(down, Shape{b});
    ASSERT_TRUE(t.has_value());
    EXPECT_NEAR(10.0 - *t, along * 0.05 + 0.5 / std::cos(pitch), 1e-9);
  }
  const Eigen::AlignedBox3d bounds = boundingBox(Shape{b});
  EXPECT_NEAR(bounds.max().z(), 5 * std::sin(pitch) + 0.5 * std::cos(pitch), 1e-9);
  EXPECT_NEAR(bounds.max().y(), 5 * std::cos(pitch) + 0.5 * std::sin(pitch), 1e-9);
}

}  // namespace
}  // namespace socc::sim
