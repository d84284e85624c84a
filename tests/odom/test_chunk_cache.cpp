// Delta chunks (docs/lcm.md "Delta chunks"): the map a ChunkCache builds from deltas equals the
// map of a complete chunk of the same sphere, voxel for voxel, while the robot drives and the
// map changes; a new map epoch or a malformed reply starts over with a complete chunk.
#include <gtest/gtest.h>

#include <random>

#include "service/chunk_reply.hpp"
#include "socc/labels.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/odom/chunk_cache.hpp"
#include "socc/odom/frame_overlay.hpp"

using namespace socc::odom;

namespace {

// A street seen from a sensor at (x, 0, 0) out to 15 m: ground, two facades and poles (sensor
// frame). The chunks reach 40 m: behind the robot, blocks stop changing.
socc::LabeledCloud streetScan(double x, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-15.0, 15.0), h(-1.7, 6.0);
  socc::LabeledCloud cloud;
  const auto add = [&](const Eigen::Vector3d& world, std::uint8_t label) {
    cloud.points.push_back((world - Eigen::Vector3d(x, 0, 0)).cast<float>());
    cloud.labels.push_back(label);
  };
  for (int i = 0; i < 3000; ++i) {
    add({x + u(rng), 0.2 * u(rng), -1.7}, socc::kRoad);
    add({x + u(rng), 8.0, h(rng)}, socc::kBuilding);
    add({x + u(rng), -8.0, h(rng)}, socc::kBuilding);
  }
  for (int pole = -3; pole <= 3; ++pole)
    for (int k = 0; k < 40; ++k) add({x + 5.0 * pole, 6.0, h(rng)}, socc::kPole);
  return cloud;
}

// GET_CHUNK as map_service answers it (map_service_queries.cpp), in process.
socc::chunk_reply_t answer(const socc::map::SemanticOccupancyMap& map,
                           const socc::chunk_request_t& r) {
  socc::map::ChunkQuery q;
  q.center = Eigen::Vector3d(r.center[0], r.center[1], r.center[2]);
  q.radius = r.radius;
  q.occupancy_threshold = r.occupancy_threshold;
  q.fields = r.fields;
  if (r.since_epoch != 0)
    q.held = socc::map::ChunkQuery::Held{
        r.since_epoch, r.since_version,
        Eigen::Vector3d(r.since_center[0], r.since_center[1], r.since_center[2]), r.since_radius};
  return socc::service::queryChunkReply(map, q);
}

void expectSameMap(const LocalMap& a, const LocalMap& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.epoch(), b.epoch());  // a delta chunk keeps its map instance
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.voxel(i).point, b.voxel(i).point) << "voxel " << i;
    EXPECT_EQ(a.voxel(i).normal, b.voxel(i).normal) << "voxel " << i;
    EXPECT_EQ(a.voxel(i).planarity, b.voxel(i).planarity) << "voxel " << i;
    EXPECT_EQ(a.voxel(i).occupancy, b.voxel(i).occupancy) << "voxel " << i;
    EXPECT_EQ(a.voxel(i).label, b.voxel(i).label) << "voxel " << i;
  }
}

constexpr double kRadius = 40.0;
constexpr double kThreshold = 0.5;

}  // namespace

TEST(ChunkCache, DeltasBuildTheMapOfACompleteChunk) {
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  ChunkCache cache(kThreshold);
  std::mt19937 rng(3);
  std::size_t delta_voxels = 0, full_voxels = 0;
  for (int frame = 0; frame < 12; ++frame) {
    const double x = 1.5 * frame;
    map.integrate(Eigen::Isometry3d(Eigen::Translation3d(x, 0, 0)), streetScan(x, rng));
    const Eigen::Vector3d center(x + 1.5, 0.0, 0.0);  // where the next frame is expected
    const socc::chunk_reply_t delta = answer(map, cache.request(center, kRadius));
    EXPECT_EQ(delta.delta_of_version >= 0, frame > 0) << "frame " << frame;
    const LocalMap cached = cache.apply(delta, center, kRadius);
    const socc::chunk_reply_t full = answer(map, featureChunkRequest(center, kRadius, kThreshold));
    ASSERT_GT(full.num_voxels, 0);
    expectSameMap(cached, LocalMap::fromChunk(full, kThreshold));
    if (frame > 0) {
      delta_voxels += static_cast<std::size_t>(delta.num_voxels);
      full_voxels += static_cast<std::size_t>(full.num_voxels);
    }
  }
  EXPECT_LT(delta_voxels, full_voxels);  // unchanged blocks stay out of the deltas
}

TEST(ChunkCache, ANewMapEpochGetsACompleteChunk) {
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  ChunkCache cache(kThreshold);
  std::mt19937 rng(5);
  map.integrate(Eigen::Isometry3d::Identity(), streetScan(0.0, rng));
  const Eigen::Vector3d center = Eigen::Vector3d::Zero();
  cache.apply(answer(map, cache.request(center, kRadius)), center, kRadius);
  map.clear();  // a new epoch: blocks vanished
  map.integrate(Eigen::Isometry3d(Eigen::Translation3d(3, 0, 0)), streetScan(3.0, rng));
  const socc::chunk_reply_t reply = answer(map, cache.request(center, kRadius));
  EXPECT_EQ(reply.delta_of_version, -1);
  expectSameMap(cache.apply(reply, center, kRadius),
                LocalMap::fromChunk(answer(map, featureChunkRequest(center, kRadius, kThreshold)),
                                    kThreshold));
}

TEST(ChunkCache, AMalformedReplyResetsTheCache) {
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  ChunkCache cache(kThreshold);
  std::mt19937 rng(7);
  map.integrate(Eigen::Isometry3d::Identity(), streetScan(0.0, rng));
  const Eigen::Vector3d center = Eigen::Vector3d::Zero();
  cache.apply(answer(map, cache.request(center, kRadius)), center, kRadius);
  EXPECT_NE(cache.request(center, kRadius).since_epoch, 0);

  socc::chunk_reply_t bad = answer(map, cache.request(center, kRadius));
  bad.delta_of_version += 7;  // a delta on an answer this client never held
  EXPECT_THROW(cache.apply(bad, center, kRadius), std::invalid_argument);
  EXPECT_EQ(cache.request(center, kRadius).since_epoch, 0);  // the next one is complete

  bad = answer(map, cache.request(center, kRadius));
  ASSERT_GT(bad.n_blocks, 0);
  bad.block_voxels[0] += 1;  // counts that do not add up to num_voxels
  EXPECT_THROW(cache.apply(bad, center, kRadius), std::invalid_argument);
  EXPECT_EQ(cache.request(center, kRadius).since_epoch, 0);
}

// A parked car drives off: rays to the wall behind clear its voxels scan by scan. Deltas leave
// out blocks whose changes were all below the map's threshold; every change a chunk can show
// (occupancy of occupied voxels, voxels turning free) still reaches it, at the map's threshold
// and below it.
std::size_t carVoxels(const LocalMap& map) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < map.size(); ++i) n += map.voxel(i).label == socc::kCar ? 1 : 0;
  return n;
}

TEST(ChunkCache, DeltasFollowVoxelsTurningFree) {
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto scan = [&](bool car) {
    socc::LabeledCloud cloud;
    for (int i = 0; i < 6000; ++i) {
      cloud.points.emplace_back(20.f, static_cast<float>(-6 + 12 * u(rng)),
                                static_cast<float>(-1.7 + 4 * u(rng)));
      cloud.labels.push_back(socc::kBuilding);
      if (!car) continue;
      cloud.points.emplace_back(static_cast<float>(9 + 2 * u(rng)),
                                static_cast<float>(-1 + 2 * u(rng)),
                                static_cast<float>(-0.7 + 0.7 * u(rng)));
      cloud.labels.push_back(socc::kCar);
    }
    return cloud;
  };
  const Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const double threshold : {kThreshold, 0.3}) {
    ChunkCache cache(threshold);
    for (int frame = 0; frame < 16; ++frame) {
      map.integrate(Eigen::Isometry3d::Identity(), scan(frame < 3));
      const LocalMap cached =
          cache.apply(answer(map, cache.request(center, kRadius)), center, kRadius);
      const socc::chunk_reply_t full = answer(map, featureChunkRequest(center, kRadius, threshold));
      expectSameMap(cached, LocalMap::fromChunk(full, threshold));
      if (frame == 2) {
        EXPECT_GT(carVoxels(cached), 20u);
      }
    }
    EXPECT_EQ(carVoxels(cache.apply(answer(map, cache.request(center, kRadius)), center, kRadius)),
              0u);  // the car is gone
  }
}

// The pipelined target (map_pipeline.hpp): a chunk with FIELD_MOMENTS, and the client's next
// frame merged into its voxels of few points, gives those voxels the normals and planarity the
// server's next chunk gives them (the first normal of some); malformed moments are refused.
TEST(PipelinedTarget, OwnPointsMergedIntoVoxelsOfFewPointsGiveTheServersFeatures) {
  socc::map::SemanticOccupancyMap map{socc::map::MapConfig{}};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto sparseWall = [&]() {  // about 3 points per 0.5 m voxel of the wall x = 6
    socc::LabeledCloud cloud;
    for (int i = 0; i < 120; ++i) {  // 40 voxels
      cloud.points.emplace_back(6.f + static_cast<float>(0.02 * (u(rng) - 0.5)),
                                static_cast<float>(-2.5 + 5.0 * u(rng)),
                                static_cast<float>(-1.0 + 2.0 * u(rng)));
      cloud.labels.push_back(socc::kBuilding);
    }
    return cloud;
  };
  const Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (int frame = 0; frame < 2; ++frame)
    map.integrate(Eigen::Isometry3d::Identity(), sparseWall());
  const socc::chunk_reply_t reply =
      answer(map, featureChunkRequest(center, kRadius, kThreshold, true));
  const LocalMap target = LocalMap::fromChunk(reply, kThreshold);
  ASSERT_GT(target.size(), 30u);
  EXPECT_EQ(target.epoch(), map.epoch());  // the frame a pose registered against it is in
  ASSERT_EQ(reply.n_moments, static_cast<std::int32_t>(target.size()));  // all of few points
  std::size_t without_normal = 0;
  for (std::size_t i = 0; i < target.size(); ++i) {
    ASSERT_TRUE(target.voxel(i).moments) << "voxel " << i;
    without_normal += target.voxel(i).planarity < 0.f ? 1 : 0;
  }
  ASSERT_GT(without_normal, 5u);

  const socc::LabeledCloud next = sparseWall();
  map.integrate(Eigen::Isometry3d::Identity(), next);
  const LocalMap served = LocalMap::fromChunk(
      answer(map, featureChunkRequest(center, kRadius, kThreshold)), kThreshold);
  const FrameSplit split = splitFrame(target, next, Eigen::Isometry3d::Identity());
  VoxelUpdates updated;
  for (const auto& [id, points] : split.into_known)
    updated.set(id, withPoints(target.voxel(id), points));
  const LocalMap merged = target.withOverlay({}, updated);
  std::size_t gained = 0, changed = 0;
  for (std::size_t i = 0; i < target.size(); ++i) {
    const MapVoxel& mine = merged.voxel(i);
    std::size_t k = 0;
    while (k < served.size() && (served.voxel(k).point - mine.point).norm() > 1e-3) ++k;
    ASSERT_LT(k, served.size()) << "voxel " << i;
    const MapVoxel& theirs = served.voxel(k);
    ASSERT_EQ(mine.planarity < 0.f, theirs.planarity < 0.f) << "voxel " << i;
    if (mine.planarity < 0.f) continue;
    gained += target.voxel(i).planarity < 0.f ? 1 : 0;
    changed += mine.planarity != target.voxel(i).planarity ? 1 : 0;
    EXPECT_GT(std::abs(mine.normal.dot(theirs.normal)), 0.9999) << "voxel " << i;
    EXPECT_NEAR(mine.planarity, theirs.planarity, 2e-3) << "voxel " << i;
  }
  EXPECT_GT(gained, 3u);    // voxels that reached five points with this frame
  EXPECT_GT(changed, 20u);  // and those whose features the frame moved

  socc::chunk_reply_t bad = reply;
  bad.n_moments -= 1;
  for (auto& row : bad.moment_mean) row.pop_back();
  for (auto& row : bad.moment_m2) row.pop_back();
  EXPECT_THROW(LocalMap::fromChunk(bad, kThreshold), std::invalid_argument);
  bad = reply;
  bad.point_count[0] = 255;  // a voxel of too many points for moments, which the reply has
  EXPECT_THROW(LocalMap::fromChunk(bad, kThreshold), std::invalid_argument);
}
