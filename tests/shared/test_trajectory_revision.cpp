// reviseTrajectory (socc/trajectory_revision.hpp): exact on synthetic trajectories.
#include <gtest/gtest.h>

#include <cmath>

#include "socc/trajectory_revision.hpp"

namespace socc {
namespace {

Eigen::Isometry3d pose(double x, double y, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, 0.3);
  return p;
}

// A curving drive: seq 10, 11, ... with output poses a metre apart.
struct Drive {
  std::vector<std::int64_t> seqs;
  Poses poses;
  explicit Drive(int n) {
    for (int i = 0; i < n; ++i) {
      seqs.push_back(10 + i);
      poses.push_back(pose(i, 0.1 * i * i, 0.05 * i));
    }
  }
};

void expectNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tol = 1e-9) {
  EXPECT_LT((a.translation() - b.translation()).norm(), tol);
  EXPECT_LT((a.linear() - b.linear()).norm(), tol);
}

TEST(TrajectoryRevision, KeyframesAtTheirOutputPosesChangeNothing) {
  const Drive d(12);
  const std::vector<KeyframeEstimate> keyframes = {
      {10, d.poses[0]}, {15, d.poses[5]}, {21, d.poses[11]}};
  const RevisedTrajectory r = reviseTrajectory(d.seqs, d.poses, keyframes);
  EXPECT_EQ(r.keyframes, 3);
  ASSERT_EQ(r.poses.size(), d.poses.size());
  for (std::size_t i = 0; i < d.poses.size(); ++i) expectNear(r.poses[i], d.poses[i]);
  EXPECT_LT(r.max_shift, 1e-9);
}

TEST(TrajectoryRevision, AConstantOffsetMovesEveryPose) {
  const Drive d(12);
  const Eigen::Isometry3d offset = pose(2.0, -1.0, 0.2);
  const std::vector<KeyframeEstimate> keyframes = {{13, offset * d.poses[3]},
                                                   {18, offset * d.poses[8]}};
  const RevisedTrajectory r = reviseTrajectory(d.seqs, d.poses, keyframes);
  EXPECT_EQ(r.keyframes, 2);
  // Before the first, between, and after the last keyframe alike.
  for (std::size_t i = 0; i < d.poses.size(); ++i) expectNear(r.poses[i], offset * d.poses[i]);
}

TEST(TrajectoryRevision, ARampBetweenTwoKeyframesIsInterpolatedBySeq) {
  const Drive d(11);
  Eigen::Isometry3d b_flat = pose(1.0, 2.0, 0.4);
  b_flat.translation().z() = 0.0;
  // Keyframes at seq 12 (no revision) and 20 (revised by b_flat): seq 16 gets half of it.
  const std::vector<KeyframeEstimate> keyframes = {{20, b_flat * d.poses[10]},
                                                   {12, d.poses[2]}};  // any order
  const RevisedTrajectory r = reviseTrajectory(d.seqs, d.poses, keyframes);
  for (int i = 0; i <= 10; ++i) {
    const double s = std::clamp((i - 2) / 8.0, 0.0, 1.0);
    Eigen::Isometry3d expected = Eigen::Isometry3d::Identity();
    expected.linear() = Eigen::AngleAxisd(0.4 * s, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    expected.translation() = s * b_flat.translation();
    SCOPED_TRACE(i);
    expectNear(r.poses[static_cast<std::size_t>(i)],
               expected * d.poses[static_cast<std::size_t>(i)]);
  }
}

TEST(TrajectoryRevision, KeyframesOfOtherSeqsAreSkipped) {
  const Drive d(5);
  const Eigen::Isometry3d offset = pose(0.5, 0.0, 0.0);
  // seq 3 (before this run's output, e.g. --resume): only seq 12 is an output pose.
  const std::vector<KeyframeEstimate> keyframes = {{3, pose(9, 9, 1)}, {12, offset * d.poses[2]}};
  const RevisedTrajectory r = reviseTrajectory(d.seqs, d.poses, keyframes);
  EXPECT_EQ(r.keyframes, 1);
  for (std::size_t i = 0; i < d.poses.size(); ++i) expectNear(r.poses[i], offset * d.poses[i]);
  EXPECT_NEAR(r.max_shift, std::hypot(0.5, 0.3), 1e-9);  // pose() puts z at 0.3
}

TEST(TrajectoryRevision, NoKeyframeLeavesThePoses) {
  const Drive d(4);
  const RevisedTrajectory r = reviseTrajectory(d.seqs, d.poses, {});
  EXPECT_EQ(r.keyframes, 0);
  for (std::size_t i = 0; i < d.poses.size(); ++i) expectNear(r.poses[i], d.poses[i]);
}

TEST(TrajectoryRevision, AMapCorrectionJumpIsNotSmeared) {
  // The robot's chain (first frame) is d.poses; from seq 15 on it outputs T x pose.
  const Drive d(11);
  const Eigen::Isometry3d T = pose(0.8, -0.3, 0.05);
  Poses output = d.poses;
  for (std::size_t i = 5; i < output.size(); ++i) output[i] = T * output[i];
  // The graph moves both keyframes by the same offset of the chain: so must every pose, on
  // either side of the jump (interpolating the output poses' revisions would smear T over
  // seq 12-18).
  const Eigen::Isometry3d offset = pose(0.2, 0.1, 0.01);
  const std::vector<KeyframeEstimate> keyframes = {{12, offset * d.poses[2]},
                                                   {18, offset * d.poses[8]}};
  const RevisedTrajectory r = reviseTrajectory(d.seqs, output, keyframes, {{15, T}});
  // Same revision at both keyframes in the first frame: every pose is offset x chain pose.
  for (std::size_t i = 0; i < output.size(); ++i) expectNear(r.poses[i], offset * d.poses[i]);
}

TEST(TrajectoryRevision, BadInputIsAClearError) {
  const Drive d(3);
  EXPECT_THROW(reviseTrajectory({10, 11}, d.poses, {}), std::invalid_argument);
  EXPECT_THROW(reviseTrajectory({10, 12, 11}, d.poses, {}), std::invalid_argument);
}

}  // namespace
}  // namespace socc
