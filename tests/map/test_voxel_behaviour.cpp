// The voxel behaviour in isolation: statistics merging, occupancy and semantic updates.
#include <gtest/gtest.h>

#include <random>

#include "socc/map/semantic_voxel.hpp"
#include "socc/map/voxel_features.hpp"

namespace socc::map {
namespace {

TEST(VoxelStatistics, IncrementalMergeMatchesBatch) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 0.1);
  const Eigen::Vector3d base(123.25, -45.75, 2.1);  // map-scale coordinates
  std::vector<Eigen::Vector3d> all;
  VoxelStats stats;
  for (int frame = 0; frame < 30; ++frame) {
    FrameAggregate agg;
    const int count = 1 + frame % 7;
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d p = base + Eigen::Vector3d(n(rng), 2.0 * n(rng), 0.3 * n(rng));
      agg.add(p);
      all.push_back(p);
    }
    mergeStatistics(stats, agg);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : all) mean += p;
  mean /= static_cast<double>(all.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : all) cov += (p - mean) * (p - mean).transpose();
  cov /= static_cast<double>(all.size() - 1);

  EXPECT_EQ(stats.count, all.size());
  EXPECT_LT((stats.meanVector() - mean).norm(), 2e-5);
  EXPECT_LT((stats.covariance() - cov).norm(), 1e-5 * std::max(1.0, cov.norm()));
  EXPECT_FLOAT_EQ(stats.first_point[0], static_cast<float>(all.front().x()));
}

TEST(VoxelStatistics, FeaturesOfAPlane) {
  FrameAggregate agg;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      agg.add(Eigen::Vector3d(0.05 * i, 0.05 * j, 1.0 + 1e-3 * ((i + j) % 2)));
  VoxelStats s;
  mergeStatistics(s, agg);
  const VoxelFeatures f = computeFeatures(s);
  ASSERT_TRUE(f.valid);
  EXPECT_GT(std::abs(f.normal.z()), 0.999);
  EXPECT_LT(f.planarity, 0.01);

  VoxelStats few;
  FrameAggregate four;
  for (int i = 0; i < 4; ++i) four.add(Eigen::Vector3d(i, 0, 0));
  mergeStatistics(few, four);
  EXPECT_FALSE(computeFeatures(few).valid);
  EXPECT_EQ(computeFeatures(few).planarity, -1.0);
}

TEST(Occupancy, HitsMissesAndClamping) {
  const MapConfig c;
  const SemanticVoxelBehaviour b(c);
  float l = 0.0f;
  VoxelStats s;
  FrameAggregate agg;
  agg.add(Eigen::Vector3d(0.1, 0.1, 0.1));
  b.onHits(l, s, agg);
  EXPECT_NEAR(l, logit(0.55), 1e-6);
  for (int i = 0; i < 100; ++i) b.onHits(l, s, agg);
  EXPECT_NEAR(l, logit(c.clamp_max), 1e-5);  // clamped so the map can still change
  // Unlabeled voxel: p_miss.
  float before = l;
  EXPECT_FALSE(b.onMiss(l, &s));
  EXPECT_NEAR(l - before, logit(0.49), 1e-6);
  for (int i = 0; i < 1000; ++i) b.onMiss(l, nullptr);
  EXPECT_NEAR(l, logit(c.clamp_min), 1e-5);
}

TEST(Occupancy, ClassDependentMisses) {
  MapConfig c;
  const SemanticVoxelBehaviour b(c);
  VoxelStats building;
  FrameAggregate agg;
  agg.add(Eigen::Vector3d::Zero(), kBuilding);
  float l = 0.0f;
  b.onHits(l, building, agg);
  EXPECT_NEAR(b.missLogOdds(&building), logit(0.498), 1e-6);

  VoxelStats car;
  FrameAggregate car_agg;
  car_agg.add(Eigen::Vector3d::Zero(), kCar);
  b.onHits(l, car, car_agg);
  EXPECT_NEAR(b.missLogOdds(&car), logit(0.475), 1e-6);

  VoxelStats unlabeled;
  FrameAggregate u;
  u.add(Eigen::Vector3d::Zero(), kUnlabeled);
  b.onHits(l, unlabeled, u);
  EXPECT_NEAR(b.missLogOdds(&unlabeled), logit(0.49), 1e-6);
  EXPECT_NEAR(b.missLogOdds(nullptr), logit(0.49), 1e-6);

  c.semantics = false;
  const SemanticVoxelBehaviour plain(c);
  EXPECT_NEAR(plain.missLogOdds(&car), logit(0.49), 1e-6);

  // A car voxel hit once (+0.20) turns free on the third miss (-0.10 each) and then asks for
  // its statistics to be dropped; a building voxel needs 26 misses (-0.008 each).
  float lc = 0.0f;
  VoxelStats s;
  b.onHits(lc, s, car_agg);
  EXPECT_FALSE(b.onMiss(lc, &s));
  EXPECT_FALSE(b.onMiss(lc, &s));
  EXPECT_TRUE(b.onMiss(lc, &s));
  float lb = 0.0f;
  VoxelStats sb;
  b.onHits(lb, sb, agg);
  int misses = 1;
  while (!b.onMiss(lb, &sb)) ++misses;
  EXPECT_EQ(misses, 26);
}

TEST(Semantics, EmaWithAlpha08) {
  const SemanticVoxelBehaviour b{MapConfig{}};
  VoxelStats s;
  float l = 0.0f;
  FrameAggregate f1;  // 3 road, 1 car
  for (int i = 0; i < 3; ++i) f1.add(Eigen::Vector3d::Zero(), kRoad);
  f1.add(Eigen::Vector3d::Zero(), kCar);
  b.onHits(l, s, f1);  // first labeled hit adopts the frequencies
  EXPECT_NEAR(s.prob(kRoad), 0.75, 2e-5);
  EXPECT_NEAR(s.prob(kCar), 0.25, 2e-5);
  EXPECT_EQ(s.label, kRoad);

  FrameAggregate f2;  // all car
  for (int i = 0; i < 2; ++i) f2.add(Eigen::Vector3d::Zero(), kCar);
  b.onHits(l, s, f2);
  EXPECT_NEAR(s.prob(kRoad), 0.8 * 0.75, 2e-5);
  EXPECT_NEAR(s.prob(kCar), 0.8 * 0.25 + 0.2, 2e-5);
  EXPECT_EQ(s.label, kRoad);  // 0.6 vs 0.4
  for (int i = 0; i < 3; ++i) b.onHits(l, s, f2);
  // road: 0.75 * 0.8^4 = 0.3072; car: 1 - 0.3072
  EXPECT_NEAR(s.prob(kRoad), 0.3072, 5e-5);
  EXPECT_NEAR(s.prob(kCar), 0.6928, 5e-5);
  EXPECT_EQ(s.label, kCar);
  float sum = 0.0f;
  for (int k = 0; k < kNumClasses; ++k) sum += s.prob(k);
  EXPECT_NEAR(sum, 1.0f, 1e-4);

  FrameAggregate unlabeled_scan;  // no labels: distribution unchanged
  unlabeled_scan.add(Eigen::Vector3d::Zero());
  const auto before = s.class_prob;
  b.onHits(l, s, unlabeled_scan);
  EXPECT_EQ(s.class_prob, before);
}

}  // namespace
}  // namespace socc::map
