#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "socc/eval/trajectory.hpp"

namespace socc::eval {
namespace {

namespace fs = std::filesystem;

fs::path tempRoot() {
  return fs::temp_directory_path() / ("socc_eval_" + std::to_string(::getpid()));
}

fs::path writeFile(const std::string& name, const std::string& text) {
  fs::create_directories(tempRoot());
  std::ofstream(tempRoot() / name) << text;
  return tempRoot() / name;
}

class TrajectoryLoading : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(tempRoot()); }
};

TEST_F(TrajectoryLoading, DetectsKittiAndTum) {
  const fs::path kitti = writeFile("k.txt", "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 4 0 1 0 5 0 0 1 6\n");
  const fs::path tum = writeFile("t.txt", "# header\n0.5 1 2 3 0 0 0 1\n");
  const Trajectory k = loadTrajectory(kitti, TrajectoryFormat::kAuto);
  ASSERT_EQ(k.poses.size(), 2u);
  EXPECT_TRUE(k.stamps.empty());
  EXPECT_DOUBLE_EQ(k.poses[1].translation().z(), 6.0);
  const Trajectory t = loadTrajectory(tum, TrajectoryFormat::kAuto);
  ASSERT_EQ(t.stamps.size(), 1u);
  EXPECT_DOUBLE_EQ(t.stamps[0], 0.5);
}

TEST_F(TrajectoryLoading, CalibMovesCameraPosesToLidar) {
  const fs::path kitti = writeFile("c.txt", "1 0 0 0 0 1 0 0 0 0 1 5\n");  // camera z forward
  const fs::path calib = writeFile("calib.txt", "Tr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n");
  const Trajectory t = loadTrajectory(kitti, TrajectoryFormat::kKitti, calib);
  EXPECT_TRUE(t.poses[0].translation().isApprox(Eigen::Vector3d(5, 0, 0)));  // LiDAR x forward
}

TEST_F(TrajectoryLoading, BadInputGivesClearErrors) {
  EXPECT_THROW(loadTrajectory("/nonexistent/poses.txt", TrajectoryFormat::kAuto),
               std::runtime_error);
  EXPECT_THROW(loadTrajectory(writeFile("bad.txt", "1 2 3\n"), TrajectoryFormat::kAuto),
               std::runtime_error);
  EXPECT_THROW(loadTrajectory(writeFile("empty.txt", "\n"), TrajectoryFormat::kAuto),
               std::runtime_error);
  EXPECT_THROW(
      loadTrajectory(writeFile("nan.txt", "1 0 0 nan 0 1 0 0 0 0 1 0\n"), TrajectoryFormat::kKitti),
      std::runtime_error);
  EXPECT_THROW(parseTrajectoryFormat("csv"), std::invalid_argument);
}

}  // namespace
}  // namespace socc::eval

namespace socc::eval {
namespace {

TEST_F(TrajectoryLoading, RejectsNonRotationsAndOrthonormalises) {
  EXPECT_THROW(loadTrajectory(writeFile("scaled.txt", "2 0 0 0 0 2 0 0 0 0 2 0\n"),
                              TrajectoryFormat::kKitti),
               std::runtime_error);
  const Trajectory t =
      loadTrajectory(writeFile("rounded.txt", "1.000001 0.001 0 0 -0.001 1 0 0 0 0 0.999999 0\n"),
                     TrajectoryFormat::kKitti);
  const Eigen::Matrix3d r = t.poses[0].linear();
  EXPECT_TRUE((r * r.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

}  // namespace
}  // namespace socc::eval
