// Region rebuilds (grid_rebuild.hpp, updateGrid): a grid brought to moved keyframes by erasing
// and integrating again only the region they reach is the grid a whole rebuild gives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "grid_rebuild.hpp"
#include "service/chunk_reply.hpp"
#include "socc/chunk_request_t.hpp"

namespace socc::consistency {
namespace {

constexpr int kKeyframes = 20;
constexpr double kSpacing = 5.0;  // [m] along x
constexpr double kRange = 20.0;   // [m] of each scan

/// A straight street: ground at z = -1.7, facades at y = +-8 with a few pillars, labelled by
/// surface. What a sensor at `at` sees of it within kRange, in its frame (no occlusion).
LabeledCloud streetScan(const Eigen::Isometry3d& at) {
  LabeledCloud cloud;
  const auto add = [&](const Eigen::Vector3d& world, std::uint8_t label) {
    const Eigen::Vector3d p = at.inverse() * world;
    if (p.norm() > kRange) return;
    cloud.points.push_back(p.cast<float>());
    cloud.labels.push_back(label);
  };
  const double x0 = at.translation().x() - kRange, x1 = at.translation().x() + kRange;
  for (double x = x0; x <= x1; x += 0.2) {
    for (double y = -8.0; y <= 8.0; y += 0.4) add({x, y, -1.7}, 9);  // road
    for (double z = -1.7; z <= 6.0; z += 0.3) {
      add({x, -8.0, z}, 13);  // building
      add({x, 8.0, z}, 13);
    }
    if (std::fmod(std::abs(x), 12.0) < 0.5)
      for (double z = -1.7; z <= 3.0; z += 0.2) add({x, 4.0, z}, 17);  // pole
  }
  return cloud;
}

std::vector<Keyframe> streetKeyframes(const map::MapConfig& config) {
  std::vector<Keyframe> keyframes(kKeyframes);
  for (int i = 0; i < kKeyframes; ++i) {
    Keyframe& k = keyframes[static_cast<std::size_t>(i)];
    k.id = i;
    k.odom_pose = Eigen::Isometry3d(Eigen::Translation3d(kSpacing * i, 0.0, 0.0));
    k.scan = compactScan(streetScan(k.odom_pose), config.voxel_size / 5.0);
  }
  return keyframes;
}

/// Everything a client can read of the map: stats and every chunk field (occupied, free,
/// features, statistics) of the whole street.
std::vector<std::uint8_t> observe(const map::SemanticOccupancyMap& map) {
  map::ChunkQuery q;
  q.center = Eigen::Vector3d(kSpacing * kKeyframes / 2.0, 0.0, 0.0);
  q.radius = kSpacing * kKeyframes;
  q.fields = chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS |
             chunk_request_t::FIELD_FREE | chunk_request_t::FIELD_INDEX;
  chunk_reply_t reply = service::queryChunkReply(map, q);
  reply.map_epoch = 0;  // random per map instance, by design
  reply.map_version = 0;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(reply.getEncodedSize()));
  reply.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const map::MapStats s = map.stats();
  for (const std::int64_t v : {s.num_voxels, s.num_occupied, s.num_free, s.num_blocks})
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  return bytes;
}

std::vector<Eigen::Isometry3d> posesOf(const std::vector<Keyframe>& keyframes) {
  std::vector<Eigen::Isometry3d> poses;
  for (const Keyframe& k : keyframes) poses.push_back(k.odom_pose);
  return poses;
}

const RegionRule kRule = regionRule(ConsistencyParams{});  // server.yaml's

TEST(GridRebuild, ARegionRebuildGivesTheGridOfAWholeRebuild) {
  const map::MapConfig config;
  std::vector<Keyframe> keyframes = streetKeyframes(config);
  map::SemanticOccupancyMap base(config);
  ASSERT_EQ(updateGrid(base, keyframes, 0, posesOf(keyframes), kRule), kKeyframes);

  // A closure moves the street's last three keyframes (0.4 m and 1 deg) and adds two more.
  std::vector<Eigen::Isometry3d> moved = posesOf(keyframes);
  for (int i = kKeyframes - 3; i < kKeyframes; ++i)
    moved[static_cast<std::size_t>(i)] = Eigen::Translation3d(0.0, 0.4, 0.0) *
                                         moved[static_cast<std::size_t>(i)] *
                                         Eigen::AngleAxisd(0.0175, Eigen::Vector3d::UnitZ());
  std::vector<Keyframe> region_keyframes = keyframes;
  for (int i = 0; i < 2; ++i) {
    Keyframe k = keyframes[static_cast<std::size_t>(i) + 3];
    k.id = kKeyframes + i;
    region_keyframes.push_back(k);
    moved.push_back(k.odom_pose);
  }
  std::vector<Keyframe> whole_keyframes = region_keyframes;

  map::SemanticOccupancyMap region = base.clone();
  const int integrated = updateGrid(region, region_keyframes, kKeyframes, moved, kRule);
  map::SemanticOccupancyMap whole(config);
  ASSERT_EQ(updateGrid(whole, whole_keyframes, 0, moved, kRule), kKeyframes + 2);

  // Compared whole, not printed: the answers are megabytes.
  EXPECT_TRUE(observe(region) == observe(whole));
  EXPECT_FALSE(observe(region) == observe(base));
  // The street's start is beyond the moved scans' reach: kept, not integrated again.
  EXPECT_LT(integrated, kKeyframes);
  EXPECT_GT(integrated, 5);
  for (std::size_t i = 0; i < region_keyframes.size(); ++i)
    EXPECT_TRUE(region_keyframes[i].grid_pose.isApprox(moved[i])) << i;
}

TEST(GridRebuild, AKeyframeMovedLessThanTheRegionShiftStaysWhereItIs) {
  const map::MapConfig config;
  std::vector<Keyframe> keyframes = streetKeyframes(config);
  map::SemanticOccupancyMap grid(config);
  updateGrid(grid, keyframes, 0, posesOf(keyframes), kRule);
  const std::vector<std::uint8_t> before = observe(grid);

  std::vector<Eigen::Isometry3d> estimates = posesOf(keyframes);
  estimates[4] = Eigen::Translation3d(0.03, 0.0, 0.0) * estimates[4];
  EXPECT_EQ(updateGrid(grid, keyframes, kKeyframes, estimates, kRule), 0);
  EXPECT_TRUE(observe(grid) == before);
  EXPECT_TRUE(keyframes[4].grid_pose.isApprox(keyframes[4].odom_pose));
}

TEST(GridRebuild, ACorrectionReachingMostKeyframesRebuildsTheWholeGrid) {
  const map::MapConfig config;
  std::vector<Keyframe> keyframes = streetKeyframes(config);
  map::SemanticOccupancyMap grid(config);
  updateGrid(grid, keyframes, 0, posesOf(keyframes), kRule);

  // Every keyframe moves 0.3 m but the fifth (0.03 m, below the region shift): a whole rebuild
  // puts it at its estimate too.
  std::vector<Eigen::Isometry3d> estimates = posesOf(keyframes);
  for (Eigen::Isometry3d& pose : estimates) pose = Eigen::Translation3d(0.0, 0.3, 0.0) * pose;
  estimates[4] = Eigen::Translation3d(0.03, 0.0, 0.0) * keyframes[4].odom_pose;
  std::vector<Keyframe> whole_keyframes = keyframes;
  EXPECT_EQ(updateGrid(grid, keyframes, kKeyframes, estimates, kRule), kKeyframes);
  EXPECT_TRUE(keyframes[4].grid_pose.isApprox(estimates[4]));
  map::SemanticOccupancyMap whole(config);
  updateGrid(whole, whole_keyframes, 0, estimates, kRule);
  EXPECT_TRUE(observe(grid) == observe(whole));
}

// rebuild_region false: every rebuild is whole (the moved keyframe's region is not used) and
// no keyframe keeps a footprint.
TEST(GridRebuild, WithoutRegionsEveryRebuildIsWholeAndKeepsNoFootprint) {
  const map::MapConfig config;
  RegionRule off = kRule;
  off.enabled = false;
  std::vector<Keyframe> keyframes = streetKeyframes(config);
  map::SemanticOccupancyMap grid(config);
  ASSERT_EQ(updateGrid(grid, keyframes, 0, posesOf(keyframes), off), kKeyframes);
  std::vector<Eigen::Isometry3d> estimates = posesOf(keyframes);
  estimates[kKeyframes - 1] = Eigen::Translation3d(0.0, 0.4, 0.0) * estimates[kKeyframes - 1];
  std::vector<Keyframe> whole_keyframes = keyframes;
  EXPECT_EQ(updateGrid(grid, keyframes, kKeyframes, estimates, off), kKeyframes);
  for (const Keyframe& k : keyframes) {
    EXPECT_TRUE(k.footprint.empty());
    EXPECT_FALSE(k.footprint_pose.has_value());
  }
  EXPECT_EQ(footprintBytes(keyframes), 0U);
  map::SemanticOccupancyMap whole(config);
  updateGrid(whole, whole_keyframes, 0, estimates, kRule);
  EXPECT_TRUE(observe(grid) == observe(whole));
}

TEST(GridRebuild, TheFootprintHoldsEveryBlockTheScanChangesAndNoOther) {
  map::MapConfig config;
  config.max_range = 10.0;
  LabeledCloud cloud;
  cloud.points = {{3.f, 0.f, 0.f}, {0.f, -40.f, 0.f}, {0.f, 0.f, 2.f}};
  cloud.labels = {1, 1, 1};
  const Eigen::Isometry3d pose(Eigen::Translation3d(100.0, 0.0, 0.0));
  map::SemanticOccupancyMap map(config);
  const std::vector<map::BlockKey> traced = map.footprint(pose, cloud);
  EXPECT_EQ(map.stats().num_blocks, 0);  // tracing changes nothing
  std::vector<map::BlockKey> listed;
  map.integrate(pose, cloud, listed);
  EXPECT_EQ(listed, traced);
  // The blocks the scan made are its footprint: the far point's ray ends at max range.
  std::vector<map::BlockKey> made;
  for (const auto& key : map.blocksChangedSince(-1)) made.emplace_back(key[0], key[1], key[2]);
  EXPECT_EQ(made, traced);
  const map::VoxelGeometry geometry(config.voxel_size);
  EXPECT_EQ(traced.front(), map::blockOf(geometry.indexOf({100.0, -10.0, 0.0})));
}

}  // namespace
}  // namespace socc::consistency
