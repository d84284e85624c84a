#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "scan_context.hpp"

namespace socc::consistency {
namespace {

// A small "street": walls, posts and a box at different heights around the sensor.
std::vector<Eigen::Vector3f> sceneAround(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-40.0f, 40.0f), h(0.0f, 8.0f);
  std::vector<Eigen::Vector3f> points;
  for (int post = 0; post < 60; ++post) {
    const float x = u(rng), y = u(rng), top = h(rng);
    for (float z = -1.7f; z < top; z += 0.3f) points.emplace_back(x, y, z);
  }
  return points;
}

std::vector<Eigen::Vector3f> turned(const std::vector<Eigen::Vector3f>& points, double yaw) {
  const Eigen::Matrix3f r =
      Eigen::AngleAxisf(static_cast<float>(yaw), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> out;
  for (const Eigen::Vector3f& p : points) out.push_back(r.transpose() * p);  // sensor turned by yaw
  return out;
}

TEST(ScanContext, SamePlaceTurnedMatchesWithItsYaw) {
  const ScanContextParams params;
  const std::vector<Eigen::Vector3f> here = sceneAround(1);
  const ScanContext a(here, params);
  for (const double yaw : {0.0, 0.6, -2.0, 3.0}) {
    const ScanContext b(turned(here, yaw), params);
    EXPECT_NEAR((a.ringKey() - b.ringKey()).norm(), 0.0, 0.05);
    const ScanContext::Match m = b.compare(a);
    // Turns between sector multiples move thin posts across bin borders.
    EXPECT_LT(m.distance, 0.2) << yaw;
    // One sector is 6 deg.
    EXPECT_NEAR(std::remainder(m.yaw - yaw, 2.0 * M_PI), 0.0, 0.11) << yaw;
  }
}

TEST(ScanContext, OtherPlaceIsFarAndEmptyIsNothing) {
  const ScanContextParams params;
  const ScanContext a(sceneAround(1), params), b(sceneAround(2), params);
  EXPECT_GT(a.compare(b).distance, 0.3);
  const ScanContext empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_DOUBLE_EQ(a.compare(empty).distance, 1.0);
  EXPECT_GT(a.bytes(), 0u);
}

}  // namespace
}  // namespace socc::consistency
