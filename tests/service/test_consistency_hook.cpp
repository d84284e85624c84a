// The consistency service behind MapService (docs/consistency.md): off by default, fed by every
// applied INTEGRATE (not by duplicates or refusals), and fed again by journal replay.
#include <gtest/gtest.h>

#include "keyframe_store.hpp"
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

keyframes_request_t keyframesOf(const std::string& robot, std::int64_t from_seq = 0,
                                std::int32_t max = 100) {
  keyframes_request_t request{};
  request.robot_id = robot;
  request.from_seq = from_seq;
  request.max_keyframes = max;
  return request;
}

TEST(ConsistencyHook, GetKeyframesGivesTheOptimizedPosesOfOneRobot) {
  test::TempDir dir;
  MapService service(withConsistency(dir.path()));
  for (int seq = 1; seq <= 10; ++seq) service.integrate(scan("robot1", seq, seq - 1.0));
  for (int seq = 1; seq <= 4; ++seq) service.integrate(scan("robot2", seq, seq + 20.0));
  service.consistency()->flush();
  const keyframes_reply_t all = service.getKeyframes(keyframesOf("robot1"));
  ASSERT_EQ(all.header.status, +reply_header_t::OK) << all.header.message;
  EXPECT_EQ(all.keyframes.robot_id, "robot1");
  EXPECT_EQ(all.keyframes.seq, (std::vector<std::int64_t>{1, 4, 7, 10}));
  ASSERT_EQ(all.keyframes.translation.size(), 3u);
  EXPECT_NEAR(all.keyframes.translation[0][3], 9.0, 1e-9);  // no closure: as integrated
  EXPECT_EQ(all.pending, 0);
  EXPECT_FALSE(all.truncated);
  const keyframes_reply_t page = service.getKeyframes(keyframesOf("robot1", 5, 1));
  EXPECT_EQ(page.keyframes.seq, (std::vector<std::int64_t>{7}));
  EXPECT_TRUE(page.truncated);
  EXPECT_EQ(service.getKeyframes(keyframesOf("robot2")).keyframes.seq,
            (std::vector<std::int64_t>{1, 4}));
  EXPECT_EQ(service.getKeyframes(keyframesOf("ghost")).header.status, +reply_header_t::NOT_FOUND);
  EXPECT_EQ(service.getKeyframes(keyframesOf("robot1", 11)).header.status,
            +reply_header_t::NOT_FOUND);
  EXPECT_EQ(service.getKeyframes(keyframesOf("robot1", 0, 0)).header.status,
            +reply_header_t::INVALID_ARGUMENT);
}

TEST(ConsistencyHook, GetKeyframesWithoutTheServiceSaysSo) {
  MapService service(test::smallConfig());
  service.integrate(scan("robot1", 1));
  const keyframes_reply_t reply = service.getKeyframes(keyframesOf("robot1"));
  EXPECT_EQ(reply.header.status, +reply_header_t::FAILED_PRECONDITION);
  EXPECT_NE(reply.header.message.find("--consistency"), std::string::npos);
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

TEST(ConsistencyHook, AnIntegratesGravityReferenceReachesItsKeyframeAlsoOnReplay) {
  // gravity_sigma 0: no reference. Keyframes at seq 1 (with), 4 (without), 7 (with).
  test::TempDir dir;
  const Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
  const auto withGravity = [](std::int64_t seq) {
    integrate_request_t request = scan("robot1", seq, seq - 1.0);
    if (seq != 4) {
      request.gravity_up[0] = 0.02f;
      request.gravity_up[2] = 0.9998f;
      request.gravity_sigma = 0.001f;
    }
    return request;
  };
  {
    MapService live(withConsistency(dir.path()));
    live.openDurability(durability, std::nullopt);
    for (int seq = 1; seq <= 7; ++seq) live.integrate(withGravity(seq));
    live.consistency()->flush();
    EXPECT_EQ(live.consistency()->stats().gravity_keyframes, 2);
    // Dropped like a killed process: the journal holds every request as sent.
  }
  std::filesystem::remove(dir.path() / "map.snap.consistency");
  MapService restored(withConsistency(dir.path()));
  restored.openDurability(durability, dir.path() / "map.snap");
  restored.consistency()->flush();
  EXPECT_EQ(restored.consistency()->stats().keyframes, 3);
  EXPECT_EQ(restored.consistency()->stats().gravity_keyframes, 2);
}

std::vector<std::int64_t> keyframeSeqs(MapService& service) {
  service.consistency()->flush();
  std::vector<std::int64_t> seqs;
  for (const auto& k : service.consistency()->keyframePoses()) seqs.push_back(k.seq);
  return seqs;
}

TEST(ConsistencyHook, ARestartResumesTheStoredKeyframesAndReplaysNoneTwice) {
  test::TempDir dir;
  const Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
  const std::filesystem::path store = dir.path() / "map.snap.consistency";
  {
    MapService live(withConsistency(dir.path()));
    live.openDurability(durability, std::nullopt);
    for (int seq = 1; seq <= 7; ++seq) live.integrate(scan("robot1", seq, seq - 1.0));
    live.consistency()->flush();
    live.checkpoint();  // the snapshot holds 3 keyframes' scans, the store their keyframes
    for (int seq = 8; seq <= 10; ++seq) live.integrate(scan("robot1", seq, seq - 1.0));
    EXPECT_EQ(keyframeSeqs(live), (std::vector<std::int64_t>{1, 4, 7, 10}));
    // Dropped like a killed process.
  }
  EXPECT_EQ(consistency::KeyframeStore::read(store).keyframes.size(), 4u);
  MapService restored(withConsistency(dir.path()));
  restored.openDurability(durability, dir.path() / "map.snap");
  // From the store, the journal's 8..10 replayed without a second keyframe 10.
  EXPECT_EQ(keyframeSeqs(restored), (std::vector<std::int64_t>{1, 4, 7, 10}));
  EXPECT_EQ(consistency::KeyframeStore::read(store).keyframes.size(), 4u);
  restored.integrate(scan("robot1", 11, 12.0));
  EXPECT_EQ(keyframeSeqs(restored), (std::vector<std::int64_t>{1, 4, 7, 10, 11}));
  EXPECT_EQ(consistency::KeyframeStore::read(store).keyframes.size(), 5u);
}

TEST(ConsistencyHook, WithoutItsStoreARestartKeepsOnlyTheReplayedKeyframes) {
  test::TempDir dir;
  const Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
  {
    MapService live(withConsistency(dir.path()));
    live.openDurability(durability, std::nullopt);
    for (int seq = 1; seq <= 7; ++seq) live.integrate(scan("robot1", seq, seq - 1.0));
    live.consistency()->flush();
    live.checkpoint();
    live.integrate(scan("robot1", 8, 9.0));
  }
  std::filesystem::remove(dir.path() / "map.snap.consistency");
  MapService restored(withConsistency(dir.path()));
  restored.openDurability(durability, dir.path() / "map.snap");
  EXPECT_EQ(keyframeSeqs(restored), (std::vector<std::int64_t>{8}));
  // A new store, marked as begun on a grid it did not see built.
  EXPECT_TRUE(consistency::KeyframeStore::read(dir.path() / "map.snap.consistency").foreign_base);
}

TEST(ConsistencyHook, ClearAndLoadStartANewStore) {
  test::TempDir dir;
  const Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
  const std::filesystem::path store = dir.path() / "map.snap.consistency";
  MapService live(withConsistency(dir.path()));
  live.openDurability(durability, std::nullopt);
  for (int seq = 1; seq <= 4; ++seq) live.integrate(scan("robot1", seq, 3.0 * seq));
  EXPECT_EQ(keyframeSeqs(live).size(), 4u);
  live.saveSnapshot(dir.path() / "other.snap");
  map_command_request_t command{};
  command.command = map_command_request_t::CLEAR;
  ASSERT_EQ(live.command(command).header.status, +reply_header_t::OK);
  EXPECT_TRUE(keyframeSeqs(live).empty());
  consistency::StoreContents c = consistency::KeyframeStore::read(store);
  EXPECT_TRUE(c.keyframes.empty());
  EXPECT_FALSE(c.foreign_base);
  command.command = map_command_request_t::LOAD;
  command.path = "other.snap";
  ASSERT_EQ(live.command(command).header.status, +reply_header_t::OK);
  c = consistency::KeyframeStore::read(store);
  EXPECT_TRUE(c.keyframes.empty());
  EXPECT_TRUE(c.foreign_base);  // the loaded grid's scans are not in it: never rebuilt
}

}  // namespace
}  // namespace socc::service
