#include <gtest/gtest.h>

#include <random>

#include "socc/chunk_features.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/labels.hpp"
#include "socc/odom/frame_overlay.hpp"
#include "socc/odom/local_map.hpp"

using namespace socc::odom;

namespace {
socc::chunk_reply_t makeChunk(const std::vector<Eigen::Vector3f>& points, std::uint8_t occupancy) {
  socc::chunk_reply_t c{};
  c.fields = socc::chunk_request_t::FIELD_FEATURES;
  c.voxel_size = 0.5;
  c.p_hit = 0.55f;
  c.block_dim = 8;
  c.num_voxels = static_cast<int>(points.size());
  c.n_blocks = c.num_voxels;  // one block entry per voxel
  c.n_index = 0;
  c.n_features = c.num_voxels;
  c.n_stats = 0;
  c.num_classes = 0;
  c.n_free = 0;
  c.block.resize(3);
  c.first_point.resize(3);  // by axis: first_point[0] = x offset of every voxel
  c.normal.resize(2);
  const double block_size = c.block_dim * c.voxel_size;
  const auto up = socc::chunk::encodeNormal(Eigen::Vector3d::UnitZ());
  for (const auto& p : points) {
    const Eigen::Vector3i key = (p.cast<double>() / block_size).array().floor().cast<int>();
    const Eigen::Vector3d corner = socc::chunk::blockCorner(key, c.block_dim, c.voxel_size);
    for (int a = 0; a < 3; ++a) {
      c.block[a].push_back(key[a]);
      c.first_point[a].push_back(socc::chunk::encodeOffset(p[a] - corner[a], block_size));
    }
    c.block_voxels.push_back(1);
    c.normal[0].push_back(up[0]);
    c.normal[1].push_back(up[1]);
    c.planarity.push_back(socc::chunk::encodePlanarity(0.01));
    c.occupancy.push_back(occupancy);
    c.label.push_back(socc::kRoad);
    c.label_prob.push_back(255);
  }
  return c;
}
}  // namespace

TEST(LocalMap, DecodesFeaturesOfAChunk) {
  const auto chunk = makeChunk({{1, 2, 3}, {4, 5, 6}}, 200);
  const LocalMap map = LocalMap::fromChunk(chunk, 0.5);
  ASSERT_EQ(map.size(), 2u);
  const MapVoxel& v = map.voxel(1);
  EXPECT_LT((v.point - Eigen::Vector3d(4, 5, 6)).norm(), 1e-4);  // the wire's 0.06 mm steps
  EXPECT_TRUE(v.normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(v.occupancy, 200.f / 255.f, 1e-6);
  EXPECT_EQ(v.label, socc::kRoad);
  EXPECT_FLOAT_EQ(v.label_prob, 1.f);
}

TEST(LocalMap, SkipsVoxelsBelowTheOccupancyThreshold) {
  EXPECT_EQ(LocalMap::fromChunk(makeChunk({{1, 2, 3}}, 100), 0.5).size(), 0u);
  EXPECT_EQ(LocalMap::fromChunk(makeChunk({{1, 2, 3}}, 128), 0.5).size(), 1u);
}

TEST(LocalMap, RejectsMalformedChunks) {
  auto chunk = makeChunk({{1, 2, 3}, {4, 5, 6}}, 200);
  auto bad = chunk;
  bad.n_features = 1;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.planarity.pop_back();
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.block_voxels[0] = 2;  // the blocks' counts do not add up to num_voxels
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.normal[1].pop_back();  // a row shorter than n_features
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.first_point.pop_back();  // a missing row
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.label[1] = 42;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.fields = 0;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.num_voxels = -3;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.voxel_size = 0.0;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.voxel_size = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
  bad = chunk;
  bad.p_hit = 1.5f;
  EXPECT_THROW(LocalMap::fromChunk(bad, 0.5), std::invalid_argument);
}

TEST(LocalMap, KeepsTheMapsResolutionEvenWhenEmpty) {
  const LocalMap map = LocalMap::fromChunk(makeChunk({}, 200), 0.5);
  EXPECT_TRUE(map.empty());
  EXPECT_DOUBLE_EQ(map.voxelSize(), 0.5);
  EXPECT_FLOAT_EQ(static_cast<float>(map.hitOccupancy()), 0.55f);
}

TEST(FrameOverlay, SplitFindsTheVoxelsTheChunkLacks) {
  // Voxel (2, 4, 6) of 0.5 m is in the chunk; (20, 20, 20) is not.
  const LocalMap map = LocalMap::fromChunk(makeChunk({{1.1f, 2.1f, 3.1f}}, 200), 0.5);
  socc::LabeledCloud cloud;
  cloud.points = {{1.4f, 2.4f, 3.4f}, {10.1f, 10.1f, 10.1f}, {1.0f, 2.0f, 3.0f}};
  cloud.labels = {socc::kRoad, socc::kCar, socc::kRoad};
  const FrameSplit split = splitFrame(map, cloud, Eigen::Isometry3d::Identity());
  ASSERT_EQ(split.outside.size(), 1u);
  EXPECT_TRUE(split.outside[0].moments.first.isApprox(Eigen::Vector3d(10.1, 10.1, 10.1), 1e-6));
  EXPECT_EQ(split.outside[0].labels[socc::kCar], 1u);
  EXPECT_TRUE(split.into_known.empty());  // the chunk sent no moments
  // The cloud taken 10 m further along x: the chunk's voxel is now where the second point lies.
  const Eigen::Isometry3d back(Eigen::Translation3d(-9.0, -8.0, -7.0));
  const FrameSplit moved = splitFrame(map, cloud, back);
  ASSERT_EQ(moved.outside.size(), 1u);  // the first and third point share a voxel there
  EXPECT_EQ(moved.outside[0].moments.count, 2u);
  EXPECT_TRUE(moved.outside[0].moments.first.isApprox(Eigen::Vector3d(-7.6, -5.6, -3.6), 1e-6));
  EXPECT_EQ(moved.outside[0].labels[socc::kRoad], 2u);
  // A map not made from a chunk knows no voxel grid.
  EXPECT_THROW(splitFrame(LocalMap(), cloud, Eigen::Isometry3d::Identity()), std::logic_error);
}

namespace {
// Every query's nearest voxel of map within 2 m is the brute-force nearest of voxels, and
// nearestTwo also gives the brute-force second-nearest distance.
void expectExactNearest(const LocalMap& map, const std::vector<MapVoxel>& voxels,
                        std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-20.f, 20.f);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d query(u(rng), u(rng), u(rng));
    const double bound = 2.0;
    std::size_t best = voxels.size();
    double best2 = bound * bound, second2 = bound * bound;
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      const double d2 = (voxels[i].point - query).squaredNorm();
      if (d2 < best2) {
        second2 = best2;
        best2 = d2;
        best = i;
      } else if (d2 < second2) {
        second2 = d2;
      }
    }
    const auto nn = map.nearest(query, bound);
    const NearestTwo two = map.nearestTwo(query, bound);
    EXPECT_NEAR(two.second_squared_distance, second2, 1e-9);
    if (best == voxels.size()) {
      EXPECT_FALSE(nn.has_value());
      EXPECT_FALSE(two.nearest.has_value());
    } else {
      ASSERT_TRUE(nn.has_value());
      EXPECT_EQ(nn->index, best);
      EXPECT_NEAR(nn->squared_distance, best2, 1e-9);
      ASSERT_TRUE(two.nearest.has_value());
      EXPECT_EQ(two.nearest->index, best);
    }
  }
}

std::vector<MapVoxel> randomVoxels(std::size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-20.f, 20.f);
  std::vector<MapVoxel> voxels(n);
  for (auto& v : voxels) v.point = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return voxels;
}
}  // namespace

TEST(LocalMap, NearestIsExactWithinTheBound) {
  std::mt19937 rng(7);
  const std::vector<MapVoxel> voxels = randomVoxels(3000, rng);
  expectExactNearest(LocalMap(voxels), voxels, rng);
  EXPECT_FALSE(LocalMap().nearest(Eigen::Vector3d::Zero(), 100.0).has_value());
}

TEST(LocalMap, AnOverlayIsSearchedWithTheMap) {
  std::mt19937 rng(11);
  const std::vector<MapVoxel> voxels = randomVoxels(3000, rng);
  const std::vector<MapVoxel> base(voxels.begin(), voxels.begin() + 2500);
  const std::vector<MapVoxel> overlay(voxels.begin() + 2500, voxels.end());
  const LocalMap map = LocalMap(base).withOverlay(overlay);
  ASSERT_EQ(map.size(), voxels.size());
  expectExactNearest(map, voxels, rng);
  // Only an overlay.
  const LocalMap only = LocalMap().withOverlay(overlay);
  expectExactNearest(only, overlay, rng);
}
