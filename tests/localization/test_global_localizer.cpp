// The server-side search of global localization: candidates from FPFH + RANSAC, before any
// client-side verification.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "../kitti_pairs.hpp"
#include "global_localizer.hpp"
#include "socc/kitti_io.hpp"

namespace fs = std::filesystem;
using namespace socc::localization;

namespace {

double degrees(const Eigen::Isometry3d& d) {
  return Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

// KITTI 08 frames 720 and 1500: the same place driven in opposite directions (148.5 deg).
TEST(GlobalLocalizer, KittiReverseRevisitIsAmongTheCandidates) {
  const fs::path dir = socc::test::kittiPairsDir("08");
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data folder absent: " << dir;
  const socc::Poses gt = socc::test::kittiGt(8, {720, 1500});

  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  map.integrate(gt[0], socc::test::kittiPairScan("08", 720));
  GlobalLocalizer localizer;
  const auto start = std::chrono::steady_clock::now();
  const LocalizeAnswer answer =
      localizer.localize(map, socc::test::kittiPairScan("08", 1500).points, std::nullopt, 4);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(answer.candidates.empty());
  for (const PoseCandidate& c : answer.candidates) {
    const Eigen::Isometry3d d = gt[1].inverse() * c.pose;
    std::printf("candidate: %d inliers (%.2f), %.2f m %.2f deg from GT\n", c.inliers,
                c.inlier_fraction, d.translation().norm(), degrees(d));
  }
  std::printf("%zu map keypoints, %zu scan keypoints, %.2f s\n", answer.map_keypoints,
              answer.scan_keypoints, seconds);
  const Eigen::Isometry3d best = gt[1].inverse() * answer.candidates.front().pose;
  EXPECT_LT(best.translation().norm(), 3.0);
  EXPECT_LT(degrees(best), 10.0);
}

// A map with nothing to match (a fleet's first robots in their own frames ask it every few
// scans): no candidates, and the scan is not described, which is most of a search's cost.
TEST(GlobalLocalizer, AnEmptyMapIsAnsweredWithoutDescribingTheScan) {
  const fs::path dir = socc::test::kittiPairsDir("08");
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data folder absent: " << dir;
  const socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  GlobalLocalizer localizer;
  const LocalizeAnswer answer =
      localizer.localize(map, socc::test::kittiPairScan("08", 1500).points, std::nullopt, 4);
  EXPECT_TRUE(answer.candidates.empty());
  EXPECT_EQ(answer.map_keypoints, 0u);
  EXPECT_EQ(answer.scan_keypoints, 0u);
  EXPECT_EQ(answer.search.draws, 0);
}
