// The consistency service behind MapService (docs/consistency.md): off by default, fed by every
// applied INTEGRATE (not by duplicates or refusals), and fed again by journal replay.
#include <gtest/gtest.h>

#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

using test::scan;

ServerConfig withConsistency(const std::filesystem::path& dir) {
  ServerConfig config = test::smallConfig(dir);
  config.consistency.enabled = true;
  config.consistency.keyframe_distance = 3.0;
  return config;
}

TEST(ConsistencyHook, OffByDefault) {
  MapService service(test::smallConfig());
  EXPECT_EQ(service.consistency(), nullptr);
}

TEST(ConsistencyHook, AppliedIntegratesMakeKeyframes) {
  test::TempDir dir;
  MapService service(withConsistency(dir.path()));
  ASSERT_NE(service.consistency(), nullptr);
  // One metre apart: keyframes at x = 0, 3, 6, 9.
  for (int seq = 1; seq <= 10; ++seq) service.integrate(scan("robot1", seq, seq - 1.0));
  EXPECT_TRUE(service.integrate(scan("robot1", 10, 42.0)).duplicate);  // not observed again
  service.consistency()->flush();
  const consistency::ConsistencyStats stats = service.consistency()->stats();
  EXPECT_EQ(stats.keyframes, 4);
  EXPECT_EQ(stats.robots, 1);
  EXPECT_NEAR(stats.travelled, 9.0, 1e-9);
  // No closure: the corrections are the identity.
  const Eigen::Isometry3d pose(Eigen::Translation3d(5.0, 0.0, 0.0));
  EXPECT_TRUE(service.consistency()->corrected("robot1", 6, pose).isApprox(pose));
}

TEST(ConsistencyHook, JournalReplayRebuildsTheKeyframes) {
  test::TempDir dir;
  const Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
  {
    MapService live(withConsistency(dir.path()));
    live.openDurability(durability, std::nullopt);
    for (int seq = 1; seq <= 7; ++seq) live.integrate(scan("robot1", seq, seq - 1.0));
    // Dropped like a killed process.
  }
  MapService restored(withConsistency(dir.path()));
  restored.openDurability(durability, dir.path() / "map.snap");
  restored.consistency()->flush();
  EXPECT_EQ(restored.consistency()->stats().keyframes, 3);  // x = 0, 3, 6
}

}  // namespace
}  // namespace socc::service
