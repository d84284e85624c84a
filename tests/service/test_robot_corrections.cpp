// Which frame each robot's INTEGRATE poses are in after a map correction (robot_corrections.hpp,
// docs/consistency.md): the first request after the swap is moved and told, later ones are not,
// and the state survives a snapshot.
#include <gtest/gtest.h>

#include "service/robot_corrections.hpp"

namespace socc::service {
namespace {

Eigen::Isometry3d xyaw(double x, double yaw = 0.0) {
  return Eigen::Translation3d(x, 0.0, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
}

TEST(RobotCorrections, TheFirstRequestAfterASwapIsMovedAndToldLaterOnesAreNot) {
  RobotCorrections c;
  const RobotCorrections::Incoming plain = c.incoming("a", 1, xyaw(1.0));
  EXPECT_TRUE(plain.map.isApprox(xyaw(1.0)));
  EXPECT_FALSE(plain.told);

  const Eigen::Isometry3d correction = xyaw(2.0, 0.1);  // raw -> corrected map
  c.offer("a", correction);
  EXPECT_EQ(c.waiting(), 1);
  const RobotCorrections::Incoming first = c.incoming("a", 2, xyaw(3.0));  // old frame
  ASSERT_TRUE(first.told);
  EXPECT_TRUE(first.map.isApprox(correction * xyaw(3.0)));
  EXPECT_TRUE(first.raw.isApprox(xyaw(3.0)));
  EXPECT_TRUE(c.toldWith("a", 2));  // a retry of seq 2 is told again
  EXPECT_FALSE(c.toldWith("a", 1));
  EXPECT_EQ(c.waiting(), 0);

  const Eigen::Isometry3d sent = correction * xyaw(4.0);  // the robot applied it
  const RobotCorrections::Incoming next = c.incoming("a", 3, sent);
  EXPECT_FALSE(next.told);
  EXPECT_TRUE(next.map.isApprox(sent));
  EXPECT_TRUE(next.raw.isApprox(xyaw(4.0)));  // the pose graph sees the odometry's frame

  // A second correction composes: the robot is told only what it has not applied yet.
  const Eigen::Isometry3d second = xyaw(2.5, 0.12);
  c.offer("a", second);
  const RobotCorrections::Incoming again = c.incoming("a", 4, correction * xyaw(5.0));
  ASSERT_TRUE(again.told);
  EXPECT_TRUE(again.map.isApprox(second * xyaw(5.0)));
  EXPECT_TRUE((*again.told * correction).isApprox(second));
}

TEST(RobotCorrections, SurviveASnapshotAndRefuseGarbage) {
  RobotCorrections c;
  c.offer("robot one", xyaw(1.0, 0.2));  // not told yet: told after a restart
  c.offer("b", xyaw(-1.0));
  c.incoming("b", 7, xyaw(0.5));
  RobotCorrections restored;
  ASSERT_TRUE(restored.parse(c.serialize()));
  EXPECT_EQ(restored.serialize(), c.serialize());
  EXPECT_EQ(restored.waiting(), 1);
  EXPECT_TRUE(restored.toldWith("b", 7));
  const RobotCorrections::Incoming first = restored.incoming("robot one", 1, xyaw(3.0));
  ASSERT_TRUE(first.told);
  EXPECT_TRUE(first.map.isApprox(xyaw(1.0, 0.2) * xyaw(3.0)));
  EXPECT_TRUE(RobotCorrections().parse(""));
  EXPECT_FALSE(restored.parse("\"x\" 1 0 nan"));
  EXPECT_FALSE(restored.parse("\"x\" 1 0 1 2 3"));
  EXPECT_EQ(restored.waiting(), 0);  // unchanged by the refused texts
}

}  // namespace
}  // namespace socc::service
