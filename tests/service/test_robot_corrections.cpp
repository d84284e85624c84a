// Which frame each robot's INTEGRATE poses are in after a map correction (robot_corrections.hpp,
// docs/consistency.md): a request registered against an older grid is moved and told, one of
// the corrected grid is taken as it is, an unknown instance is in the frame last told, and the
// state survives a snapshot (also one written before map instances were named).
#include <gtest/gtest.h>

#include "service/robot_corrections.hpp"

namespace socc::service {
namespace {

Eigen::Isometry3d xyaw(double x, double yaw = 0.0) {
  return Eigen::Translation3d(x, 0.0, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
}

constexpr std::int64_t kUnknown = 0;

TEST(RobotCorrections, ARequestOfTheOldGridIsMovedAndToldLaterOnesAreNot) {
  RobotCorrections c;
  c.serving(100);
  const RobotCorrections::Incoming plain = c.incoming("a", 1, xyaw(1.0), 100);
  EXPECT_TRUE(plain.map.isApprox(xyaw(1.0)));
  EXPECT_FALSE(plain.told);

  const Eigen::Isometry3d correction = xyaw(2.0, 0.1);  // raw -> corrected map
  c.corrected(200, {{"a", correction}});
  EXPECT_EQ(c.waiting(), 1);
  const RobotCorrections::Incoming first = c.incoming("a", 2, xyaw(3.0), 100);  // old grid
  ASSERT_TRUE(first.told);
  EXPECT_TRUE(first.map.isApprox(correction * xyaw(3.0)));
  EXPECT_TRUE(first.raw.isApprox(xyaw(3.0)));
  EXPECT_TRUE(c.toldWith("a", 2));  // a retry of seq 2 is told again
  EXPECT_FALSE(c.toldWith("a", 1));
  EXPECT_EQ(c.waiting(), 0);

  const Eigen::Isometry3d sent = correction * xyaw(4.0);  // the robot applied it
  const RobotCorrections::Incoming next = c.incoming("a", 3, sent, 200);
  EXPECT_FALSE(next.told);
  EXPECT_TRUE(next.map.isApprox(sent));
  EXPECT_TRUE(next.raw.isApprox(xyaw(4.0)));  // the pose graph sees the odometry's frame

  // A second correction composes: the robot is told only what it has not applied yet. An
  // unknown instance (an older client) is the frame it was last told.
  const Eigen::Isometry3d second = xyaw(2.5, 0.12);
  c.corrected(300, {{"a", second}});
  const RobotCorrections::Incoming again = c.incoming("a", 4, correction * xyaw(5.0), kUnknown);
  ASSERT_TRUE(again.told);
  EXPECT_TRUE(again.map.isApprox(second * xyaw(5.0)));
  EXPECT_TRUE((*again.told * correction).isApprox(second));
}

TEST(RobotCorrections, APoseOfTheCorrectedGridIsNotMovedASecondTime) {
  RobotCorrections c;
  c.serving(100);
  c.incoming("a", 1, xyaw(1.0), 100);
  const Eigen::Isometry3d correction = xyaw(2.0, 0.1);
  c.corrected(200, {{"a", correction}});
  // The robot relocalized against the corrected grid (or registered its next scan against it)
  // before its next Integrate: its pose is in the new frame already.
  const Eigen::Isometry3d relocalized = xyaw(7.0, 0.3);
  const RobotCorrections::Incoming in = c.incoming("a", 2, relocalized, 200);
  EXPECT_FALSE(in.told);
  EXPECT_TRUE(in.map.isApprox(relocalized));
  EXPECT_TRUE(in.raw.isApprox(correction.inverse() * relocalized));
  EXPECT_EQ(c.waiting(), 0);
  // A robot the correction did not name keeps its frame.
  EXPECT_TRUE(c.incoming("b", 1, xyaw(3.0), 100).map.isApprox(xyaw(3.0)));

  // Two corrections later, a pose of the middle grid is moved by the second one only, and a
  // restart (a new instance in the same generation) changes nothing.
  const Eigen::Isometry3d second = xyaw(2.5, 0.12);
  c.corrected(300, {{"a", second}});
  c.serving(400);  // restarted
  const RobotCorrections::Incoming middle = c.incoming("a", 3, correction * xyaw(6.0), 200);
  ASSERT_TRUE(middle.told);
  EXPECT_TRUE(middle.map.isApprox(second * xyaw(6.0)));
  EXPECT_TRUE((*middle.told * correction).isApprox(second));
  const RobotCorrections::Incoming restarted = c.incoming("a", 4, second * xyaw(6.5), 400);
  EXPECT_FALSE(restarted.told);
  EXPECT_TRUE(restarted.raw.isApprox(xyaw(6.5)));
}

TEST(RobotCorrections, SurviveASnapshotAndRefuseGarbage) {
  RobotCorrections c;
  c.serving(1);
  c.corrected(2, {{"robot one", xyaw(1.0, 0.2)}, {"b", xyaw(-1.0)}});
  c.incoming("b", 7, xyaw(0.5), 1);                     // told; "robot one" is told after a restart
  EXPECT_TRUE(RobotCorrections().serialize().empty());  // nothing corrected: nothing written
  RobotCorrections restored;
  ASSERT_TRUE(restored.parse(c.serialize()));
  EXPECT_EQ(restored.serialize(), c.serialize());
  EXPECT_EQ(restored.waiting(), 1);
  EXPECT_TRUE(restored.toldWith("b", 7));
  restored.serving(3);
  const RobotCorrections::Incoming first = restored.incoming("robot one", 1, xyaw(3.0), 1);
  ASSERT_TRUE(first.told);
  EXPECT_TRUE(first.map.isApprox(xyaw(1.0, 0.2) * xyaw(3.0)));
  // The corrected instance of before the restart is still known: taken as it is.
  EXPECT_FALSE(restored.incoming("b", 8, xyaw(-1.0) * xyaw(2.0), 2).told);
  EXPECT_TRUE(RobotCorrections().parse(""));
  EXPECT_FALSE(restored.parse("\"x\" 1 0 nan"));
  EXPECT_FALSE(restored.parse("\"x\" 1 0 1 2 3"));
  EXPECT_FALSE(restored.parse("generation 1\nepoch 5 2\n"));  // a generation not reached
  EXPECT_FALSE(restored.parse("generation 1\nrobot \"x\" 0 -1 1 2\n"));
  EXPECT_FALSE(restored.parse("generation 1\nrubbish\n"));
  EXPECT_EQ(restored.waiting(), 0);  // unchanged by the refused texts
}

TEST(RobotCorrections, ARobotAwayForManyCorrectionsKeepsABoundedStateThatStillParses) {
  RobotCorrections c;
  c.serving(1);
  // Every rebuild names the robot (its keyframes are in the graph) while it sends nothing.
  for (int k = 1; k <= 100; ++k) c.corrected(1 + k, {{"away", xyaw(0.01 * k)}});
  RobotCorrections restored;
  ASSERT_TRUE(restored.parse(c.serialize()));  // 64 instances and their frames, not 100
  EXPECT_EQ(restored.serialize(), c.serialize());
  // A pose of a remembered grid (generation 80) is moved by what changed since.
  const RobotCorrections::Incoming old_grid = restored.incoming("away", 1, xyaw(5.8), 81);
  ASSERT_TRUE(old_grid.told);
  EXPECT_TRUE(old_grid.map.isApprox(xyaw(6.0)));
  // An unknown instance: the frame last told (never told: its first frame).
  const RobotCorrections::Incoming unknown = c.incoming("away", 1, xyaw(5.0), kUnknown);
  ASSERT_TRUE(unknown.told);
  EXPECT_TRUE(unknown.map.isApprox(xyaw(6.0)));
}

TEST(RobotCorrections, ASnapshotOfBeforeMapInstancesWereNamedIsRead) {
  // The text of a server before integrate_request_t::map_epoch: name, told seq, whether a
  // correction waits, the frame last told, the waiting correction, the last correction told.
  const std::string identity = " 1 0 0 0 0 1 0 0 0 0 1 0";
  const std::string legacy =
      "\"robot one\" -1 1" + identity + " 1 0 0 1 0 1 0 0 0 0 1 0" + identity + "\n";
  RobotCorrections c;
  ASSERT_TRUE(c.parse(legacy));
  EXPECT_EQ(c.waiting(), 1);
  c.serving(9);
  const RobotCorrections::Incoming first = c.incoming("robot one", 1, xyaw(3.0), kUnknown);
  ASSERT_TRUE(first.told);
  EXPECT_TRUE(first.map.isApprox(xyaw(4.0)));
}

}  // namespace
}  // namespace socc::service
