// Scans of hand-made worlds: points lie on the analytic surfaces, carry the primitive's label,
// and follow the documented motion-distortion convention.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/sim/scan_simulator.hpp"

namespace socc::sim {
namespace {

constexpr std::uint16_t kLabel = 81;

// A sensor moving along +x at `speed` from the origin, level.
Trajectory straightMotion(double speed) {
  Poses keyframes;
  for (int k = 0; k <= 20; ++k) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation().x() = speed * 0.1 * k;
    keyframes.push_back(p);
  }
  return Trajectory(keyframes, 0.1);
}

Scene singlePrimitive(const Shape& shape, double speed = 0.0) {
  return Scene{World({{shape, kLabel}}, {}, nullptr, {}, 1.73), straightMotion(speed)};
}

LidarModel noiseless() {
  LidarModel m = lidarPreset("vlp16");
  m.range_noise = 0.0;
  return m;
}

TEST(ScanSimulator, SpherePointsLieOnTheSurfaceWithItsLabel) {
  const Sphere sphere{{8, 1, 0}, 2.5};
  const SimulatedScan scan = simulateScan(singlePrimitive(sphere), noiseless(), 0.0, 0, {});
  ASSERT_GT(scan.points.size(), 100u);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    EXPECT_NEAR((scan.points[i].cast<double>() - sphere.center).norm(), sphere.radius, 1e-4);
    EXPECT_EQ(scan.labels[i], kLabel);
  }
}

TEST(ScanSimulator, RangesMatchAnalyticIntersections) {
  // Every returned point, re-cast as a ray, is at exactly the analytic intersection distance.
  const Box box = makeBox({6, -2, 0.5}, {2, 3, 4}, 0.4);
  const SimulatedScan scan = simulateScan(singlePrimitive(box), noiseless(), 0.0, 0, {});
  ASSERT_GT(scan.points.size(), 100u);
  for (const auto& p : scan.points) {
    const Eigen::Vector3d q = p.cast<double>();
    const auto t = intersect(Ray{Eigen::Vector3d::Zero(), q.normalized()}, box);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, q.norm(), 1e-4);
  }
}

TEST(ScanSimulator, NoiseAndDropout) {
  const Sphere sphere{{8, 0, 0}, 3.0};
  LidarModel m = noiseless();
  const std::size_t clean = simulateScan(singlePrimitive(sphere), m, 0.0, 0, {}).points.size();
  m.range_noise = 0.05;
  m.dropout = 0.3;
  const SimulatedScan noisy = simulateScan(singlePrimitive(sphere), m, 0.0, 0, {});
  const double kept = static_cast<double>(noisy.points.size()) / static_cast<double>(clean);
  EXPECT_NEAR(kept, 0.7, 0.05);
  double sq = 0.0;
  for (const auto& p : noisy.points) {
    const double e = (p.cast<double>() - sphere.center).norm() - sphere.radius;
    sq += e * e;
  }
  // Range noise along the ray is roughly radial on the sensor-facing cap.
  EXPECT_NEAR(std::sqrt(sq / static_cast<double>(noisy.points.size())), 0.05, 0.015);
}

TEST(ScanSimulator, WithoutMotionDistortedEqualsUndistorted) {
  const Box wall = makeBox({15, 0, 0}, {1, 30, 10});
  const Scene scene = singlePrimitive(wall, 0.0);
  const SimulatedScan a = simulateScan(scene, lidarPreset("vlp16"), 0.3, 3, {false, 5});
  const SimulatedScan b = simulateScan(scene, lidarPreset("vlp16"), 0.3, 3, {true, 5});
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.times, b.times);
}

TEST(ScanSimulator, DistortionFollowsTheDocumentedConvention) {
  // Moving at 10 m/s towards a wall whose face is at x = 14.5: a point taken at sweep time tau
  // is in the sensor frame at tau, so x + speed * tau is the wall's x for every point.
  const double speed = 10.0;
  const Box wall = makeBox({15, 0, 0}, {1, 60, 20});
  const SimulatedScan scan =
      simulateScan(singlePrimitive(wall, speed), noiseless(), 0.0, 0, {true, 1});
  ASSERT_GT(scan.points.size(), 100u);
  float min_x = 1e9f;
  float max_x = -1e9f;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    EXPECT_GE(scan.times[i], 0.f);
    EXPECT_LT(scan.times[i], 0.1f);
    EXPECT_NEAR(scan.points[i].x() + speed * scan.times[i], 14.5, 1e-4);
    min_x = std::min(min_x, scan.points[i].x());
    max_x = std::max(max_x, scan.points[i].x());
  }
  EXPECT_GT(max_x - min_x, 0.3f);  // the distortion is visible in the raw points
}

TEST(ScanSimulator, MoversMoveBetweenFrames) {
  // One car driving along a straight route at 10 m/s, 8 m left of a static sensor.
  const auto route = std::make_shared<Path>(straightPath(200.0, 1.73));
  const Mover car{{{makeBox({0, 0, 0.75}, {4.3, 1.8, 1.5}), 252}}, 100.0, 10.0, 8.0};
  Poses still(2, Eigen::Isometry3d::Identity());
  still[0].translation() = still[1].translation() = Eigen::Vector3d(100, 0, 1.73);
  const Scene scene{World({}, {}, route, {car}, 1.73), Trajectory(still, 1.0)};
  const auto centroid = [&](double t) {
    const SimulatedScan s = simulateScan(scene, lidarPreset("vlp32"), t, 0, {});
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      EXPECT_EQ(s.labels[i], 252u);
      c += s.points[i].cast<double>();
    }
    EXPECT_GT(s.points.size(), 50u);
    return Eigen::Vector3d(c / static_cast<double>(std::max<std::size_t>(1, s.points.size())));
  };
  const Eigen::Vector3d a = centroid(0.0);
  const Eigen::Vector3d b = centroid(0.2);
  EXPECT_NEAR(b.x() - a.x(), 2.0, 0.3);  // moved ~2 m forward (the visible side shifts a bit)
  EXPECT_NEAR(b.y(), a.y(), 0.1);
}

}  // namespace
}  // namespace socc::sim
