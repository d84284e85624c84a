#include <gtest/gtest.h>

#include <random>

#include "socc/odom/odom_config.hpp"
#include "socc/odom/voxel_downsampling.hpp"

using socc::LabeledCloud;
using socc::odom::semanticVoxelDownsample;

namespace {
std::array<double, socc::kNumClasses> paperFactors() {
  return socc::odom::classFactors(socc::odom::OdomConfig{});
}
}  // namespace

TEST(VoxelDownsampling, KeepsTheMeanPerVoxelAndClass) {
  LabeledCloud c;
  // Two building points in voxel (0,0,0), one car point in the same voxel, one building point
  // in voxel (1,0,0).
  c.points = {{0.1f, 0.2f, 0.3f}, {0.5f, 0.6f, 0.7f}, {0.9f, 0.9f, 0.9f}, {1.5f, 0.5f, 0.5f}};
  c.labels = {socc::kBuilding, socc::kBuilding, socc::kCar, socc::kBuilding};
  const LabeledCloud out = semanticVoxelDownsample(c, 1.0, paperFactors());
  ASSERT_EQ(out.size(), 3u);
  ASSERT_EQ(out.labels.size(), 3u);
  EXPECT_TRUE(out.points[0].isApprox(Eigen::Vector3f(0.3f, 0.4f, 0.5f)));  // a mean, not a sample
  EXPECT_EQ(out.labels[0], socc::kBuilding);
  EXPECT_TRUE(out.points[1].isApprox(Eigen::Vector3f(0.9f, 0.9f, 0.9f)));
  EXPECT_EQ(out.labels[1], socc::kCar);
  EXPECT_TRUE(out.points[2].isApprox(Eigen::Vector3f(1.5f, 0.5f, 0.5f)));
}

// Column-major scans (all rings per azimuth step) revisit each voxel column after column, more
// voxels than the lookup memo holds: every voxel keeps the mean of all its points, in the order
// of their first points.
TEST(VoxelDownsampling, RevisitedVoxelsKeepTheirMeansInFirstPointOrder) {
  LabeledCloud c;
  const int voxels = 600, columns = 5;
  for (int col = 0; col < columns; ++col)
    for (int v = 0; v < voxels; ++v) {
      c.points.emplace_back(static_cast<float>(v % 30) + 0.1f * static_cast<float>(col) + 0.05f,
                            static_cast<float>(v / 30) + 0.5f, 0.5f);
      c.labels.push_back(socc::kBuilding);
    }
  const LabeledCloud out = semanticVoxelDownsample(c, 1.0, paperFactors());  // building: 1
  ASSERT_EQ(out.size(), static_cast<std::size_t>(voxels));
  for (int v = 0; v < voxels; ++v) {
    const Eigen::Vector3f mean(static_cast<float>(v % 30) + 0.25f,
                               static_cast<float>(v / 30) + 0.5f, 0.5f);
    EXPECT_TRUE(out.points[v].isApprox(mean, 1e-6f)) << v << ": " << out.points[v].transpose();
  }
}

// A scan large enough to be summed in two halves at once: voxels of both halves keep the mean of
// all their points and times; the voxels only the second half has follow, in the order of their
// first points.
TEST(VoxelDownsampling, AScanSummedInHalvesIsSummedAsOne) {
  LabeledCloud c;
  const int voxels = 10000;
  for (int pass = 0; pass < 2; ++pass)
    for (int v = 0; v < voxels; ++v) {
      c.points.emplace_back(static_cast<float>(v % 100) + 0.25f + 0.5f * static_cast<float>(pass),
                            static_cast<float>(v / 100) + 0.5f, 0.5f);
      c.labels.push_back(socc::kBuilding);
      c.times.push_back(0.01f * static_cast<float>(pass));
    }
  for (int v = 0; v < 100; ++v) {  // in the second half only
    c.points.emplace_back(static_cast<float>(v) + 0.5f, -0.5f, 0.5f);
    c.labels.push_back(socc::kBuilding);
    c.times.push_back(0.02f);
  }
  const LabeledCloud out = semanticVoxelDownsample(c, 1.0, paperFactors());  // building: 1
  ASSERT_EQ(out.size(), static_cast<std::size_t>(voxels + 100));
  for (int v = 0; v < voxels; ++v) {
    const Eigen::Vector3f mean(static_cast<float>(v % 100) + 0.5f,
                               static_cast<float>(v / 100) + 0.5f, 0.5f);
    EXPECT_TRUE(out.points[v].isApprox(mean, 1e-6f)) << v << ": " << out.points[v].transpose();
    EXPECT_FLOAT_EQ(out.times[v], 0.005f) << v;
  }
  for (int v = 0; v < 100; ++v)
    EXPECT_TRUE(out.points[voxels + v].isApprox(
        Eigen::Vector3f(static_cast<float>(v) + 0.5f, -0.5f, 0.5f), 1e-6f));
}

TEST(VoxelDownsampling, DropsHumansAndUsesClassVoxelSizes) {
  LabeledCloud c;
  for (int i = 0; i < 100; ++i) {
    const float x = 0.05f + 0.1f * i;  // a 10 m line
    c.points.push_back({x, 0.f, 0.f});
    c.labels.push_back(socc::kPerson);
    c.points.push_back({x, 5.f, 0.f});
    c.labels.push_back(socc::kPole);  // alpha 0.75 -> voxel 0.75 m
    c.points.push_back({x, 10.f, 0.f});
    c.labels.push_back(socc::kRoad);  // alpha 0.8 -> 0.8 m
    c.points.push_back({x, 15.f, 0.f});
    c.labels.push_back(socc::kBuilding);  // 1.0 m
  }
  const LabeledCloud out = semanticVoxelDownsample(c, 1.0, paperFactors());
  std::array<int, socc::kNumClasses> count{};
  for (auto l : out.labels) ++count[l];
  EXPECT_EQ(count[socc::kPerson], 0);
  EXPECT_EQ(count[socc::kBuilding], 10);
  EXPECT_EQ(count[socc::kPole], 14);  // ceil(10 / 0.75)
  EXPECT_EQ(count[socc::kRoad], 13);  // ceil(10 / 0.8)
}

TEST(VoxelDownsampling, UnlabeledCloudUsesFactorOne) {
  LabeledCloud c;
  for (int i = 0; i < 50; ++i) c.points.push_back({0.05f + 0.1f * i, 0.f, 0.f});
  const LabeledCloud out = semanticVoxelDownsample(c, 1.0, paperFactors());
  EXPECT_EQ(out.size(), 5u);
  for (auto l : out.labels) EXPECT_EQ(l, 0);
}

TEST(VoxelDownsampling, AdaptiveVoxelSizeApproachesTheTargetCount) {
  // A 100 m x 100 m plane sampled every 5 cm: count ~ (100 / v)^2.
  socc::odom::AdaptiveVoxelSize v(0.3, 0.1, 10.0, 2500);
  for (int frame = 0; frame < 10; ++frame) {
    const double n = (100.0 / v.size()) * (100.0 / v.size());
    v.update(static_cast<std::size_t>(n));
  }
  EXPECT_NEAR(v.size(), 2.0, 0.05);
  socc::odom::AdaptiveVoxelSize bounded(1.0, 0.5, 1.5, 2500);
  bounded.update(1);
  EXPECT_DOUBLE_EQ(bounded.size(), 0.5);
  bounded.update(1000000);
  EXPECT_DOUBLE_EQ(bounded.size(), 1.0);  // step limited to x2
}

TEST(VoxelDownsampling, WithAMotionItIsTheDownsampledDeskewedCloud) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-20.f, 20.f), time(0.f, 0.1f);
  LabeledCloud c;
  for (int i = 0; i < 5000; ++i) {
    c.points.emplace_back(coord(rng), coord(rng), coord(rng) / 10.f);
    c.labels.push_back(i % 3 == 0 ? socc::kCar : socc::kBuilding);
    c.times.push_back(time(rng));
  }
  const socc::odom::Vector6d twist = (socc::odom::Vector6d() << 15, 1, 0, 0.05, 0, 0.8).finished();
  const socc::odom::SweepMotion motion(c, twist, 0.05);
  const LabeledCloud fused = semanticVoxelDownsample(c, 0.8, paperFactors(), &motion);
  const LabeledCloud apart =
      semanticVoxelDownsample(socc::odom::deskew(c, twist, 0.05), 0.8, paperFactors());
  EXPECT_EQ(fused.points, apart.points);  // bit for bit
  EXPECT_EQ(fused.labels, apart.labels);
  EXPECT_EQ(fused.times, apart.times);
  c.times.clear();  // no times: no motion to apply
  EXPECT_TRUE(socc::odom::SweepMotion(c, twist, 0.05).identity());
}
