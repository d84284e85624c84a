// The compact FIELD_FEATURES encoding (socc/chunk_features.hpp): what survives the wire.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "socc/chunk_features.hpp"

using namespace socc::chunk;

TEST(ChunkFeatures, OffsetsRoundTripWithinHalfAStep) {
  const double block = 4.0, step = block / 65535.0;
  for (const double offset : {0.0, 1e-7, 0.5, 2.0, 3.14159, 3.9999, 4.0})
    EXPECT_LE(std::abs(decodeOffset(encodeOffset(offset, block), block) - offset), 0.5 * step)
        << offset;
  // A float first point just past its block's edge is clamped onto it.
  EXPECT_DOUBLE_EQ(decodeOffset(encodeOffset(-1e-6, block), block), 0.0);
  EXPECT_DOUBLE_EQ(decodeOffset(encodeOffset(4.0 + 1e-6, block), block), 4.0);
}

TEST(ChunkFeatures, MeanOffsetsAndScatterRoundTripWithinHalfAStep) {
  const double voxel = 0.5, step = voxel / 32767.0;
  for (const double offset : {0.0, 1e-7, -0.25, 0.1234, -0.4999, 0.5})
    EXPECT_LE(std::abs(decodeMeanOffset(encodeMeanOffset(offset, voxel), voxel) - offset),
              0.5 * step)
        << offset;
  EXPECT_DOUBLE_EQ(decodeMeanOffset(encodeMeanOffset(0.6, voxel), voxel), voxel);  // clamped
  const std::uint32_t count = 7;
  const double range = count * voxel * voxel;
  for (const double value : {0.0, 0.01, -0.3, 1.5})
    EXPECT_LE(std::abs(decodeScatter(encodeScatter(value, count, voxel), count, voxel) - value),
              0.5 * range / 32767.0)
        << value;
}

TEST(ChunkFeatures, NormalsRoundTripWithinAHundredthOfADegree) {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3d n(g(rng), g(rng), g(rng));
    if (i < 6) n = Eigen::Vector3d::Unit(i % 3) * (i < 3 ? 1.0 : -1.0);  // the poles and axes
    n.normalize();
    const auto q = encodeNormal(n);
    const double angle = std::acos(std::clamp(decodeNormal(q[0], q[1]).dot(n), -1.0, 1.0));
    worst = std::max(worst, angle);
  }
  EXPECT_LT(worst * 180.0 / M_PI, 0.01);
}

TEST(ChunkFeatures, PlanarityInAByteAndUnknownKept) {
  for (const double tau : {0.0, 0.01, 0.0999, 0.1, 0.2, 1.0 / 3.0})
    EXPECT_LE(std::abs(decodePlanarity(encodePlanarity(tau)) - tau), 0.5 / 762.0 + 1e-12) << tau;
  EXPECT_EQ(encodePlanarity(-1.0), kUnknownPlanarity);
  EXPECT_EQ(decodePlanarity(kUnknownPlanarity), -1.0);
}

TEST(ChunkFeatures, BlockListsMustAddUpToTheVoxels) {
  socc::chunk_reply_t r{};
  r.num_voxels = 3;
  r.block_dim = 8;
  r.n_blocks = 2;
  r.block_voxels = {1, 2};
  EXPECT_EQ(checkBlocks(r), "");
  r.block_voxels = {1, 1};
  EXPECT_NE(checkBlocks(r), "");
  r.block_voxels = {4, -1};
  EXPECT_NE(checkBlocks(r), "");
  r.block_voxels = {1, 2};
  r.block_dim = 0;
  EXPECT_NE(checkBlocks(r), "");
}
