// The office corridor: builds on every route, keeps the route clear, is deterministic, and (unlike
// the plain corridor) has surfaces facing along the corridor axis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {
namespace {

SceneOptions officeOptions(const std::string& route, std::size_t frames, std::uint64_t seed = 1) {
  SceneOptions o;
  o.type = SceneType::kOffice;
  o.route = route;
  o.frames = frames;
  o.seed = seed;
  return o;
}

// Horizontal distance from xy to the primitive, if it overlaps heights [z0, z1].
double horizontalGap(const Primitive& p, const Eigen::Vector2d& xy, double z0, double z1) {
  const Eigen::AlignedBox3d bb = boundingBox(p.shape);
  if (bb.max().z() < z0 || bb.min().z() > z1) return kInf;
  if (const auto* b = std::get_if<Box>(&p.shape)) {
    const Eigen::Vector2d d = xy - b->center.head<2>();
    const double lx = b->cos_yaw * d.x() + b->sin_yaw * d.y();
    const double ly = -b->sin_yaw * d.x() + b->cos_yaw * d.y();
    return Eigen::Vector2d(std::max(std::abs(lx) - b->half_extents.x(), 0.0),
                           std::max(std::abs(ly) - b->half_extents.y(), 0.0))
        .norm();
  }
  if (const auto* c = std::get_if<Cylinder>(&p.shape))
    return std::max((xy - c->axis_xy).norm() - c->radius, 0.0);
  const auto& s = std::get<Sphere>(p.shape);
  return std::max((xy - s.center.head<2>()).norm() - s.radius, 0.0);
}

// Smallest horizontal distance from the sensor path to anything from the floor to 2.2 m.
double routeClearance(const Scene& scene, double duration) {
  const double floor_z = scene.world.planes().front().offset;
  double gap = kInf;
  for (double t = 0.0; t <= duration; t += 0.05) {
    const Eigen::Vector2d xy = scene.trajectory.poseAt(t).translation().head<2>();
    for (const Primitive& p : scene.world.statics().primitives())
      gap = std::min(gap, horizontalGap(p, xy, floor_z, floor_z + 2.2));
  }
  return gap;
}

// Fraction of VLP-16 returns (every 0.5 deg) whose surface normal has a component above 0.5
// along the direction of travel; normals from two neighbouring rays hitting the same surface.
double axialNormalFraction(const Scene& scene, double t) {
  const Eigen::Isometry3d pose = scene.trajectory.poseAt(t);
  const WorldSnapshot world = scene.world.at(t);
  const Eigen::Vector3d axis = pose.linear().col(0);
  const auto hit = [&](double azimuth, double elevation) -> std::optional<Eigen::Vector3d> {
    const Eigen::Vector3d d =
        pose.linear() * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                        std::cos(elevation) * std::sin(azimuth),
                                        std::sin(elevation));
    const auto h = world.cast({pose.translation(), d}, 50.0);
    if (!h) return std::nullopt;
    return pose.translation() + h->range * d;
  };
  std::size_t hits = 0;
  std::size_t axial = 0;
  for (const double elevation_deg : lidarPreset("vlp16").elevations_deg) {
    const double el = elevation_deg * M_PI / 180;
    for (int i = 0; i < 720; ++i) {
      const double az = i * M_PI / 360;
      const auto p0 = hit(az, el);
      const auto p1 = hit(az + 1e-3, el);
      const auto p2 = hit(az, el + 1e-3);
      if (!p0 || !p1 || !p2) continue;
      const Eigen::Vector3d n = (*p1 - *p0).cross(*p2 - *p0);
      if (n.norm() < 1e-12) continue;
      ++hits;
      if (std::abs(n.normalized().dot(axis)) > 0.5) ++axial;
    }
  }
  return hits ? static_cast<double>(axial) / hits : 0.0;
}

double meanAxialFraction(const Scene& scene, double duration) {
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) sum += axialNormalFraction(scene, duration * k / 8);
  return sum / 8;
}

std::vector<double> worldDigest(const Scene& scene) {
  std::vector<double> v;
  for (const Primitive& p : scene.world.statics().primitives()) {
    const Eigen::AlignedBox3d bb = boundingBox(p.shape);
    v.insert(v.end(), {bb.min().x(), bb.min().y(), bb.min().z(), bb.max().x(), bb.max().y(),
                       bb.max().z(), static_cast<double>(p.label)});
  }
  return v;
}

TEST(OfficeScene, HasFeaturesFurnitureAndIsEnclosed) {
  EXPECT_EQ(parseSceneType("office"), SceneType::kOffice);
  const Scene scene = buildScene(officeOptions("auto", 100));
  std::map<std::uint16_t, int> labels;
  for (const Primitive& p : scene.world.statics().primitives()) ++labels[p.label];
  EXPECT_GT(labels[raw::kBuilding], 250);      // walls, doors, pillars, room walls
  EXPECT_GE(labels[raw::kOtherObject], 5);     // cabinets, radiators, desks
  EXPECT_GE(labels[raw::kOtherStructure], 2);  // ceiling beams
  const SimulatedScan scan = simulateScan(scene, lidarPreset("vlp16"), 2.0, 20, {});
  EXPECT_GT(scan.points.size(), 25000u);  // enclosed: nearly every ray returns
}

TEST(OfficeScene, KeepsTheRouteClearOnEveryRoute) {
  for (const char* route : {"straight", "zigzag", "circle", "figure8"}) {
    const Scene scene = buildScene(officeOptions(route, 300));
    EXPECT_GE(routeClearance(scene, 30.0), 1.19) << route;
  }
}

TEST(OfficeScene, SameSeedSameWorld) {
  const Scene a = buildScene(officeOptions("auto", 50, 7));
  const Scene b = buildScene(officeOptions("auto", 50, 7));
  EXPECT_EQ(worldDigest(a), worldDigest(b));
  EXPECT_NE(worldDigest(a), worldDigest(buildScene(officeOptions("auto", 50, 8))));
  const SimulatedScan sa = simulateScan(a, lidarPreset("vlp16"), 1.0, 10, {true, 7});
  const SimulatedScan sb = simulateScan(b, lidarPreset("vlp16"), 1.0, 10, {true, 7});
  EXPECT_EQ(sa.points, sb.points);
  EXPECT_EQ(sa.labels, sb.labels);
}

TEST(OfficeScene, ConstrainsTheCorridorAxisUnlikeThePlainCorridor) {
  SceneOptions corridor = officeOptions("auto", 100);
  corridor.type = SceneType::kCorridor;
  const double plain = meanAxialFraction(buildScene(corridor), 10.0);
  const double office = meanAxialFraction(buildScene(officeOptions("auto", 100)), 10.0);
  EXPECT_LT(plain, 0.005);
  EXPECT_GT(office, 0.1);
}

TEST(OfficeScene, FollowsAZigzag) {
  const Scene scene = buildScene(officeOptions("zigzag", 100));
  double max_y = 0.0;
  for (double t = 0.0; t < 10.0; t += 0.5)
    max_y = std::max(max_y, std::abs(scene.trajectory.poseAt(t).translation().y()));
  EXPECT_GT(max_y, 1.0);
  // Walls of the other legs already face along each leg (the plain zigzag has ~24 %).
  EXPECT_GT(meanAxialFraction(scene, 10.0), 0.1);
  const SimulatedScan scan = simulateScan(scene, lidarPreset("vlp16"), 3.0, 30, {});
  EXPECT_GT(scan.points.size(), 25000u);
}

}  // namespace
}  // namespace socc::sim
