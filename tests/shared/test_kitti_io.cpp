#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../temp_dir.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"

namespace fs = std::filesystem;

namespace socc {
namespace {

fs::path tempDir() {
  return socc::testing::processTempDir().path();
}

TEST(KittiIo, BinRoundTrip) {
  const fs::path f = tempDir() / "a.bin";
  Points pts = {{1, 2, 3}, {-4, 5.5f, 6}};
  std::vector<float> refl = {0.1f, 0.9f};
  writeKittiBin(f, pts, &refl);
  std::vector<float> r2;
  const Points back = readKittiBin(f, &r2);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1], pts[1]);
  EXPECT_FLOAT_EQ(r2[1], 0.9f);
}

TEST(KittiIo, TruncatedBinIsAClearError) {
  const fs::path f = tempDir() / "bad.bin";
  std::ofstream(f, std::ios::binary) << "abcdefg";
  try {
    readKittiBin(f);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("multiple of 16"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readKittiBin(tempDir() / "missing.bin"), std::runtime_error);
}

TEST(KittiIo, PosesRoundTripAndBadLines) {
  const fs::path f = tempDir() / "poses.txt";
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translate(Eigen::Vector3d(1, 2, 3));
  p.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  writeKittiPoses(f, {Eigen::Isometry3d::Identity(), p});
  const Poses back = readKittiPoses(f);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_TRUE(back[1].isApprox(p, 1e-8));
  std::ofstream(f) << "1 2 3\n";
  EXPECT_THROW(readKittiPoses(f), std::runtime_error);
  std::ofstream(f) << "1 0 0 nan 0 1 0 0 0 0 1 0\n";
  EXPECT_THROW(readKittiPoses(f), std::runtime_error);
}

TEST(KittiIo, TumRoundTrip) {
  const fs::path f = tempDir() / "traj.tum";
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.rotate(Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 1, 0).normalized()));
  p.pretranslate(Eigen::Vector3d(-1, 0.5, 2));
  writeTumPoses(f, {p}, {12.5});
  std::vector<double> stamps;
  const Poses back = readTumPoses(f, &stamps);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_DOUBLE_EQ(stamps[0], 12.5);
  EXPECT_TRUE(back[0].isApprox(p, 1e-6));
}

TEST(KittiIo, RealKittiData) {
  const fs::path data = fs::path(SOCC_SHARED_DATA_DIR) / "kitti_00_first16";
  if (!fs::exists(data)) GTEST_SKIP() << "../shared/data not present: " << data;
  const KittiSequence seq = listKittiSequence(data);
  ASSERT_EQ(seq.scans.size(), 16u);
  const Points pts = readKittiBin(seq.scans[0]);
  EXPECT_GT(pts.size(), 100000u);
  ASSERT_FALSE(seq.labels[0].empty());
  const auto labels = readSemanticKittiLabels(seq.labels[0]);
  EXPECT_EQ(labels.size(), pts.size());
  int road = 0;
  for (auto l : labels) road += mapSemanticKittiLabel(l) == kRoad;
  EXPECT_GT(road, 1000);
  const Eigen::Isometry3d tr = readKittiCalibTr(data / "calib.txt");
  const Poses lidar = cameraToLidarPoses(readKittiPoses(data / "poses.txt"), tr);
  ASSERT_GE(lidar.size(), 16u);
  // The car drives forward along the LiDAR x axis.
  EXPECT_GT((lidar[0].inverse() * lidar[10]).translation().x(), 5.0);
}

// The data folder's GT: sequence 00 in the LiDAR frame agrees with kitti_00_first16's poses
// read through its own calib.txt; sequences without a calibration there are a clear error.
TEST(KittiIo, GtOfASequenceInTheLidarFrame) {
  const fs::path data = SOCC_SHARED_DATA_DIR;
  if (!fs::exists(data / "kitti_gt")) GTEST_SKIP() << "../shared/data not present: " << data;
  const Poses gt = readKittiGtLidarPoses(data / "kitti_gt", 0);
  const Poses first16 = readKittiLidarPoses(data / "kitti_00_first16");
  ASSERT_GE(gt.size(), first16.size());
  for (std::size_t i = 0; i < first16.size(); ++i)
    EXPECT_TRUE(gt[i].isApprox(first16[i], 1e-6)) << "frame " << i;
  EXPECT_GT(readKittiGtLidarPoses(data / "kitti_gt", 8).size(), 1500u);
  for (const int sequence : {-1, 3, 11}) {
    try {
      readKittiGtLidarPoses(data / "kitti_gt", sequence);
      ADD_FAILURE() << sequence << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("no LiDAR calibration"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace socc
