// ScanNormals: the surface a scan shows around each of its points, or none.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/odom/scan_normals.hpp"

using namespace socc::odom;

namespace {
socc::Points scanNormals(const socc::Points& points, double radius, double planarity_threshold,
                         std::vector<std::uint8_t> on_ground = {}) {
  const ScanNormals normals(points, radius, planarity_threshold, std::move(on_ground));
  socc::Points out;
  for (std::size_t i = 0; i < points.size(); ++i) out.push_back(normals.at(i));
  return out;
}
}  // namespace

TEST(ScanNormals, RingsOnAWallGiveTheWallsNormalALoneRingGivesNone) {
  socc::Points wall;  // three rings 0.3 m apart on the plane y = 5, points 0.25 m apart
  for (int ring = 0; ring < 3; ++ring)
    for (int k = -8; k <= 8; ++k) wall.push_back({0.25f * k, 5.f, 0.3f * ring});
  const socc::Points normals = scanNormals(wall, 1.0, 0.1);
  ASSERT_EQ(normals.size(), wall.size());
  for (const Eigen::Vector3f& n : normals) EXPECT_NEAR(std::abs(n.y()), 1.f, 1e-3f);

  socc::Points ring;  // one ring: a line, its normal undefined
  for (int k = -8; k <= 8; ++k) ring.push_back({0.25f * k, 5.f, 0.f});
  for (const Eigen::Vector3f& n : scanNormals(ring, 1.0, 0.1)) EXPECT_EQ(n.squaredNorm(), 0.f);

  socc::Points few(wall.begin(), wall.begin() + 4);  // too few points for a plane
  for (const Eigen::Vector3f& n : scanNormals(few, 1.0, 0.1)) EXPECT_EQ(n.squaredNorm(), 0.f);
  socc::Points scattered;  // a blob: no plane
  for (int i = 0; i < 30; ++i)
    scattered.push_back({std::sin(1.7f * i), std::cos(2.3f * i), std::sin(0.9f * i + 1.f)});
  int planes = 0;
  for (const Eigen::Vector3f& n : scanNormals(scattered, 3.0, 0.1)) planes += n.squaredNorm() > 0;
  EXPECT_EQ(planes, 0);
}

// A ring across a curved surface (a car's side, a trunk) is a flat curve: fitted alone it gives
// the plane of the beam's cone, which tilts with the sensor, not the surface's normal. Two rings
// across the same surface give its normal.
TEST(ScanNormals, OneRingAcrossACurvedSurfaceGivesNoNormalTwoRingsDo) {
  const auto ringAt = [](double elevation_deg, socc::Points& out) {
    const double e = elevation_deg * M_PI / 180.0;
    for (int k = -10; k <= 10; ++k) {  // a bulge: the range grows away from azimuth 0
      const double a = 0.02 * k, r = 8.0 + 10.0 * a * a;
      out.push_back(Eigen::Vector3d(r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a),
                                    r * std::sin(e))
                        .cast<float>());
    }
  };
  socc::Points one;
  ringAt(-5.0, one);
  for (const Eigen::Vector3f& n : scanNormals(one, 1.0, 0.1)) EXPECT_EQ(n.squaredNorm(), 0.f);

  socc::Points two;  // a VLP-16's neighbouring rings, 2 deg apart: 0.28 m at 8 m
  ringAt(-5.0, two);
  ringAt(-3.0, two);
  int planes = 0;
  for (const Eigen::Vector3f& n : scanNormals(two, 1.0, 0.1)) planes += n.squaredNorm() > 0;
  EXPECT_GT(planes, 0);
}

// A ring across the ground is a circle around the sensor in the ground's plane: one ring's
// neighbours give the ground's normal, where the points are labelled ground (a ring across a
// curved object, above, is not).
TEST(ScanNormals, OneRingAcrossTheGroundGivesTheGroundsNormalWhereLabelledGround) {
  socc::Points ring;  // a VLP-16's -7 deg ring on flat ground 1.7 m below: 13.8 m away
  const double r = 1.7 / std::tan(7.0 * M_PI / 180.0);
  for (int k = -20; k <= 20; ++k) {
    const double a = 0.04 * k;
    ring.push_back(Eigen::Vector3d(r * std::cos(a), r * std::sin(a), -1.7).cast<float>());
  }
  for (const Eigen::Vector3f& n : scanNormals(ring, 3.0, 0.1)) EXPECT_EQ(n.squaredNorm(), 0.f);
  const socc::Points normals =
      scanNormals(ring, 3.0, 0.1, std::vector<std::uint8_t>(ring.size(), 1));
  for (const Eigen::Vector3f& n : normals) EXPECT_NEAR(std::abs(n.z()), 1.f, 1e-3f);
}
