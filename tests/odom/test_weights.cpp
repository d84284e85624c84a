#include <gtest/gtest.h>

#include <cmath>

#include "socc/labels.hpp"
#include "socc/odom/registration.hpp"
#include "socc/odom/weights.hpp"

using namespace socc::odom;

TEST(Weights, GemanMcClureIsOneAtZeroAndDecreasing) {
  const double k = 0.5;
  EXPECT_DOUBLE_EQ(gemanMcClureWeight(0.0, k), 1.0);
  EXPECT_DOUBLE_EQ(gemanMcClureWeight(0.25, k), k * k / ((k + 0.25) * (k + 0.25)));
  double last = 1.0;
  for (double r2 = 0.01; r2 < 10.0; r2 *= 2.0) {
    const double w = gemanMcClureWeight(r2, k);
    EXPECT_LT(w, last);
    EXPECT_GT(w, 0.0);
    last = w;
  }
}

TEST(Weights, OccupancyIsPowerGamma) {
  EXPECT_DOUBLE_EQ(occupancyWeight(0.7, 1.5), std::pow(0.7, 1.5));
  EXPECT_DOUBLE_EQ(occupancyWeight(1.0, 1.5), 1.0);
  EXPECT_DOUBLE_EQ(occupancyWeight(0.5, 0.0), 1.0);
}

TEST(Weights, OccupancyTableIsBitForBitThePower) {
  const OccupancyWeights table(1.5);
  for (int b = 0; b < 256; ++b) {
    const float p = static_cast<float>(b) / 255.f;  // a chunk's occupancy byte, decoded
    EXPECT_EQ(table(p), occupancyWeight(p, 1.5)) << b;
  }
  for (const float p : {0.7f, 0.123456f, 1e-6f})  // not a byte: computed
    EXPECT_EQ(table(p), occupancyWeight(p, 1.5));
}

TEST(Weights, SemanticMatchRule) {
  EXPECT_TRUE(labelsMatch(13, 13));
  EXPECT_TRUE(labelsMatch(0, 13));
  EXPECT_TRUE(labelsMatch(13, 0));
  EXPECT_FALSE(labelsMatch(13, 1));
  EXPECT_DOUBLE_EQ(semanticWeight(13, 13, 0.8, 0.25), 0.25 + 0.75 * 0.8);
  // Unlabeled on either side is neutral, whatever the voxel's label probability.
  EXPECT_DOUBLE_EQ(semanticWeight(0, 13, 0.6, 0.25), 1.0);
  EXPECT_DOUBLE_EQ(semanticWeight(13, 0, 0.0, 0.25), 1.0);
  EXPECT_DOUBLE_EQ(semanticWeight(0, 0, 0.0, 0.25), 1.0);
  EXPECT_DOUBLE_EQ(semanticWeight(13, 1, 0.9, 0.25), 0.25);
}

namespace {
MapVoxel voxel(float planarity, Eigen::Vector3d normal) {
  MapVoxel v;
  v.point = Eigen::Vector3d(1, 2, 3);
  v.normal = normal;
  v.planarity = planarity;
  v.occupancy = 0.8f;
  v.label = socc::kBuilding;
  v.label_prob = 0.9f;
  return v;
}
}  // namespace

TEST(Weights, PlanarClassification) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(isPlanar(voxel(0.0f, n), 0.1));
  EXPECT_TRUE(isPlanar(voxel(0.099f, n), 0.1));
  EXPECT_FALSE(isPlanar(voxel(0.1f, n), 0.1));  // tau < tau_planar, strictly
  EXPECT_FALSE(isPlanar(voxel(0.3f, n), 0.1));
  EXPECT_FALSE(isPlanar(voxel(-1.f, n), 0.1));  // fewer than 5 points: unknown
  EXPECT_FALSE(isPlanar(voxel(0.01f, Eigen::Vector3d::Zero()), 0.1));
}

TEST(Weights, CorrespondenceWeightIsTheProductOfThePapersFactors) {
  RegistrationParams params;  // gamma 1.5, w_lower 0.25
  const double sigma = 0.9;   // kernel 0.3
  const Eigen::Vector3d p(1.1, 2.2, 3.3);

  const MapVoxel planar = voxel(0.02f, Eigen::Vector3d::UnitZ());
  const Correspondence cp = evaluateCorrespondence(p, socc::kBuilding, planar, sigma, params);
  EXPECT_TRUE(cp.planar);
  EXPECT_NEAR(cp.squared_residual, 0.3 * 0.3, 1e-12);  // point-to-plane: along the normal only
  const double expected_pl =
      gemanMcClureWeight(0.09, 0.3) * std::pow(0.8, 1.5) * (0.25 + 0.75 * 0.9);
  EXPECT_NEAR(cp.weight, expected_pl, 1e-6);

  const MapVoxel scattered = voxel(0.3f, Eigen::Vector3d::UnitZ());
  const Correspondence cs = evaluateCorrespondence(p, socc::kCar, scattered, sigma, params);
  EXPECT_FALSE(cs.planar);
  EXPECT_NEAR(cs.squared_residual, 0.01 + 0.04 + 0.09, 1e-12);  // point-to-point
  const double expected_po = gemanMcClureWeight(0.14, 0.3) * std::pow(0.8, 1.5) * 0.25;  // no match
  EXPECT_NEAR(cs.weight, expected_po, 1e-6);
  EXPECT_GE(cs.weight, 0.0);
  EXPECT_LE(cp.weight, 1.0);
}

TEST(Weights, VoxelsOfUnknownGeometryArePairedOnlyWhenAskedFor) {
  MapVoxel sparse;  // fewer than 5 points: no planarity, no normal
  sparse.point = Eigen::Vector3d(1.0, 0.0, 0.0);
  sparse.occupancy = 1.f;
  RegistrationParams params;
  const Eigen::Vector3d p(1.1, 0.0, 0.0);
  const Eigen::Vector3d scan_normal(1.0, 0.0, 0.0);
  // Default: along the scan's own normal only; a point without one is not paired.
  EXPECT_GT(evaluateCorrespondence(p, 0, sparse, 1.0, params, scan_normal).weight, 0.5);
  EXPECT_EQ(evaluateCorrespondence(p, 0, sparse, 1.0, params).weight, 0.0);
  params.sparse_point_pairs = true;  // the paper's pairing: to the voxel's first point
  EXPECT_GT(evaluateCorrespondence(p, 0, sparse, 1.0, params).weight, 0.5);
  params.sparse_voxel_pairs = false;
  EXPECT_EQ(evaluateCorrespondence(p, 0, sparse, 1.0, params).weight, 0.0);
  EXPECT_EQ(evaluateCorrespondence(p, 0, sparse, 1.0, params, scan_normal).weight, 0.0);
  sparse.planarity = 0.2f;  // known, non-planar geometry: point-to-point as in the paper
  EXPECT_GT(evaluateCorrespondence(p, 0, sparse, 1.0, params).weight, 0.5);
}

TEST(Weights, VoxelsOfUnknownGeometryArePairedAlongTheScansSurface) {
  // A sparse voxel's first point 0.3 m along a wall from the scan point, 0.02 m off the wall:
  // along the scan's normal only the 0.02 m count (no pull along the wall).
  MapVoxel sparse;
  sparse.point = Eigen::Vector3d(0.3, 0.0, 0.0);
  sparse.occupancy = 1.f;
  const RegistrationParams params;
  const Eigen::Vector3d p(0.0, 0.02, 0.0);
  const Correspondence along = evaluateCorrespondence(p, 0, sparse, 1.0, params, {0.0, 1.0, 0.0});
  EXPECT_TRUE(along.planar);
  EXPECT_NEAR(along.squared_residual, 0.02 * 0.02, 1e-12);
  const Correspondence to_point = evaluateCorrespondence(p, 0, sparse, 1.0, params);
  EXPECT_FALSE(to_point.planar);
  EXPECT_NEAR(to_point.squared_residual, 0.3 * 0.3 + 0.02 * 0.02, 1e-12);
  // A voxel of known geometry keeps its own classification.
  sparse.planarity = 0.2f;
  EXPECT_FALSE(evaluateCorrespondence(p, 0, sparse, 1.0, params, {0.0, 1.0, 0.0}).planar);
}
