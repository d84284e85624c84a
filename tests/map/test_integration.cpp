// Scan integration through the facade: hits vs rays, max range, moving objects, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "socc/chunk_features.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/map/block_region.hpp"
#include "socc/map/semantic_voxel.hpp"
#include "test_helpers.hpp"

namespace socc::map {
namespace {

using test::query;

ChunkQuery boxQuery(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::int32_t fields,
                    double threshold = 0.5) {
  ChunkQuery q;
  q.shape = ChunkQuery::Shape::kBox;
  q.box_min = lo;
  q.box_max = hi;
  q.fields = fields;
  q.occupancy_threshold = threshold;
  return q;
}

TEST(Integration, HitVoxelIsNeverMissedBySameScan) {
  SemanticOccupancyMap map{MapConfig{}};
  LabeledCloud c;
  c.points = {Eigen::Vector3f(5.1f, 0.1f, 0.1f), Eigen::Vector3f(10.1f, 0.1f, 0.1f)};
  const IntegrationResult r = map.integrate(Eigen::Isometry3d::Identity(), c);
  EXPECT_EQ(r.voxels_hit, 2);
  EXPECT_EQ(r.points_used, 2);
  const auto reply =
      query(map, boxQuery({5.0, 0.0, 0.0}, {5.4, 0.4, 0.4}, chunk_request_t::FIELD_STATS));
  ASSERT_EQ(reply.num_voxels, 1);
  EXPECT_NEAR(reply.log_odds[0], logit(0.55), 1e-6);
  // Voxels between are free (missed once each), and counted.
  const auto free =
      query(map, boxQuery({1.0, 0.0, 0.0}, {4.9, 0.4, 0.4}, chunk_request_t::FIELD_FREE));
  EXPECT_EQ(free.num_voxels, 0);
  EXPECT_EQ(free.n_free, 8);  // x in [1, 4.9]: voxel centres 1.25 .. 4.75
  const MapStats s = map.stats();
  EXPECT_EQ(s.num_occupied, 2);
  EXPECT_EQ(s.num_voxels, 2 + 19);  // 21 voxels along x from 0 to 10
  EXPECT_EQ(r.voxels_touched, 21);
}

TEST(Integration, FarPointsOnlyClearUpToMaxRange) {
  MapConfig cfg;
  cfg.max_range = 20.0;
  SemanticOccupancyMap map(cfg);
  LabeledCloud c;
  c.points = {Eigen::Vector3f(30.1f, 0.1f, 0.1f)};
  const IntegrationResult r = map.integrate(Eigen::Isometry3d::Identity(), c);
  EXPECT_EQ(r.voxels_hit, 0);
  EXPECT_EQ(r.points_used, 0);
  const auto near =
      query(map, boxQuery({15.0, 0.0, 0.0}, {19.9, 0.4, 0.4}, chunk_request_t::FIELD_FREE, 0.5));
  EXPECT_EQ(near.n_free, 10);
  const auto far =
      query(map, boxQuery({20.6, -1.0, -1.0}, {40.0, 1.0, 1.0}, chunk_request_t::FIELD_FREE, 0.5));
  EXPECT_EQ(far.n_free + far.num_voxels, 0);
}

TEST(Integration, MovingObjectLeavesNoGhost) {
  SemanticOccupancyMap map{MapConfig{}};
  const LabeledCloud wall = test::wall(20.0, 4.0, 0.1, kBuilding);
  LabeledCloud with_car = wall;
  test::append(with_car, test::wall(10.0, 1.0, 0.1, kCar));
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 5; ++i) map.integrate(pose, with_car);

  const ChunkQuery car_box =
      boxQuery({9.0, -1.5, -1.5}, {11.0, 1.5, 1.5}, chunk_request_t::FIELD_FEATURES);
  const auto before = query(map, car_box);
  ASSERT_GT(before.num_voxels, 10);
  for (int i = 0; i < before.num_voxels; ++i) EXPECT_EQ(before.label[i], kCar);

  std::int32_t freed = 0;
  for (int i = 0; i < 15; ++i) freed += map.integrate(pose, wall).voxels_freed;
  const auto after = query(map, car_box);
  EXPECT_EQ(after.num_voxels, 0) << "car voxels survived the object leaving";
  EXPECT_GE(freed, before.num_voxels);
  const auto wall_reply =
      query(map, boxQuery({19.5, -3.0, -3.0}, {20.5, 3.0, 3.0}, chunk_request_t::FIELD_FEATURES));
  EXPECT_GT(wall_reply.num_voxels, 100);

  // The car comes back: fresh statistics, the first point is from the new scan.
  LabeledCloud car_again = wall;
  LabeledCloud moved = test::wall(10.0, 1.0, 0.1, kCar);
  for (auto& p : moved.points) p.x() = 10.3f;
  test::append(car_again, moved);
  map.integrate(pose, car_again);
  map.integrate(pose, car_again);
  map.integrate(pose, car_again);
  map.integrate(pose, car_again);
  map.integrate(pose, car_again);
  map.integrate(pose, car_again);
  const auto back =
      query(map, boxQuery({9.0, -1.5, -1.5}, {11.0, 1.5, 1.5},
                          chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS));
  ASSERT_GT(back.num_voxels, 0);
  const std::vector<Eigen::Vector3d> first = socc::chunk::firstPoints(back);
  ASSERT_EQ(first.size(), static_cast<std::size_t>(back.num_voxels));
  for (int i = 0; i < back.num_voxels; ++i) {
    EXPECT_NEAR(first[i].x(), 10.3, 1e-4);  // the wire's 0.06 mm steps
    EXPECT_EQ(back.count[i] % 6, 0);        // only the 6 new scans' points
  }
}

class BadInput : public ::testing::Test {
 protected:
  BadInput() : map_(makeConfig()) {
    map_.integrate(Eigen::Isometry3d::Identity(), test::randomCloud(200, 5.0, 1));
  }
  static MapConfig makeConfig() {
    MapConfig c;
    c.max_points_per_scan = 1000;
    return c;
  }
  // integrate() requires valid input (the service validates each request once, before its
  // journal): validate() is the map's one check of content.
  void expectRejected(const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                      const std::string& fragment) {
    const std::string msg = map_.validate(pose, cloud);
    EXPECT_NE(msg.find(fragment), std::string::npos) << "message: '" << msg << "'";
  }
  SemanticOccupancyMap map_;
};

TEST_F(BadInput, NonFinitePoints) {
  LabeledCloud c = test::randomCloud(10, 5.0, 2);
  c.points[3].y() = std::numeric_limits<float>::quiet_NaN();
  expectRejected(Eigen::Isometry3d::Identity(), c, "point 3 is not finite");
  c.points[3].y() = std::numeric_limits<float>::infinity();
  expectRejected(Eigen::Isometry3d::Identity(), c, "point 3 is not finite");
}

TEST_F(BadInput, LabelsAndSizes) {
  LabeledCloud c = test::randomCloud(10, 5.0, 3);
  c.labels.pop_back();
  expectRejected(Eigen::Isometry3d::Identity(), c, "label count 9 != point count 10");
  c = test::randomCloud(10, 5.0, 3);
  c.labels[4] = 200;
  expectRejected(Eigen::Isometry3d::Identity(), c, "label 200 of point 4");
  c = test::randomCloud(10, 5.0, 3);
  c.times.resize(3);
  expectRejected(Eigen::Isometry3d::Identity(), c, "time count");
  expectRejected(Eigen::Isometry3d::Identity(), test::randomCloud(1001, 5.0, 4), "too many points");
}

TEST_F(BadInput, AbsurdPoses) {
  const LabeledCloud c = test::randomCloud(10, 5.0, 5);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(1e9, 0, 0);
  expectRejected(far, c, "translation exceeds");
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 2.0;
  expectRejected(scaled, c, "rotation");
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = std::nan("");
  expectRejected(nan, c, "not finite");
  LabeledCloud far_point = c;
  far_point.points[0].x() = 2e5f;
  expectRejected(Eigen::Isometry3d::Identity(), far_point, "point 0 lies beyond");
}

// Points are judged in the map frame: a sensor near max_abs_coordinate (100 km) rejects the
// points its pose carries beyond it and keeps those it turns back inside.
TEST_F(BadInput, PointsBeyondTheMapAreJudgedAfterThePose) {
  Eigen::Isometry3d edge = Eigen::Isometry3d::Identity();
  edge.translation() = Eigen::Vector3d(99990.0, 0.0, 0.0);
  LabeledCloud c = test::randomCloud(10, 5.0, 6);
  c.points[3] = Eigen::Vector3f(20.f, 0.f, 0.f);
  expectRejected(edge, c, "point 3 lies beyond");
  edge.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ(map_.validate(edge, c), "");  // x 20 turned to -20: inside
}

TEST(Integration, EmptyCloudAndUnlabeledCloud) {
  SemanticOccupancyMap map{MapConfig{}};
  const IntegrationResult r = map.integrate(Eigen::Isometry3d::Identity(), LabeledCloud{});
  EXPECT_EQ(r.voxels_touched, 0);
  EXPECT_EQ(map.version(), 1);
  LabeledCloud c = test::randomCloud(100, 5.0, 9);
  c.labels.clear();
  map.integrate(Eigen::Isometry3d::Identity(), c);
  ChunkQuery q;
  q.radius = 100.0;
  q.fields = chunk_request_t::FIELD_FEATURES;
  const auto reply = query(map, q);
  ASSERT_GT(reply.num_voxels, 0);
  for (int i = 0; i < reply.num_voxels; ++i) {
    EXPECT_EQ(reply.label[i], 0);
    EXPECT_EQ(reply.label_prob[i], 0);
  }
}

// A region integration (region rebuilds, docs/consistency.md) changes the region's voxels as a
// whole integration does and nothing else; erase() makes them unknown again; clone() copies.
TEST(Integration, ARegionIntegrationChangesItsBlocksAsAWholeOneAndNothingElse) {
  const LabeledCloud scan = test::wall(12.0, 6.0, 0.1, 13);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  SemanticOccupancyMap whole{MapConfig{}}, part{MapConfig{}};
  whole.integrate(pose, scan);
  // The wall's half at y > 0 and the rays' second half: the blocks of voxels in x 6..13 m,
  // y 0.5..7 m, z -7..7 m.
  const VoxelGeometry geometry(whole.config().voxel_size);
  const BlockKey lo = blockOf(geometry.indexOf({6.0, 0.5, -7.0}));
  const BlockKey hi = blockOf(geometry.indexOf({13.0, 7.0, 7.0}));
  std::vector<BlockKey> blocks;
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) blocks.emplace_back(x, y, z);
  BlockRegion region;
  region.add(blocks);
  part.integrate(pose, scan, region);
  int inside = 0, outside = 0;
  for (double x = 0.25; x < 13.0; x += 0.5)
    for (double y = -6.25; y < 6.5; y += 0.5) {
      const Eigen::Vector3d p(x, y, 0.25);
      const BlockKey key = blockOf(VoxelGeometry(0.5).indexOf(p));
      if (region.contains(key)) {
        EXPECT_EQ(part.occupancyAt(p), whole.occupancyAt(p)) << p.transpose();
        inside += whole.occupancyAt(p) >= 0.0 ? 1 : 0;
      } else {
        EXPECT_EQ(part.occupancyAt(p), -1.0) << p.transpose();
        outside += whole.occupancyAt(p) >= 0.0 ? 1 : 0;
      }
    }
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 50);

  SemanticOccupancyMap copy = whole.clone();
  EXPECT_EQ(copy.stats().num_voxels, whole.stats().num_voxels);
  EXPECT_EQ(copy.version(), whole.version());
  EXPECT_NE(copy.epoch(), whole.epoch());
  const std::int64_t epoch = copy.epoch();
  copy.erase(region);
  EXPECT_NE(copy.epoch(), epoch);
  EXPECT_EQ(copy.stats().num_voxels + part.stats().num_voxels, whole.stats().num_voxels);
  EXPECT_EQ(copy.stats().num_occupied + part.stats().num_occupied, whole.stats().num_occupied);
  EXPECT_EQ(copy.occupancyAt({12.25, 3.25, 0.25}), -1.0);
  EXPECT_EQ(copy.occupancyAt({12.25, -3.25, 0.25}), whole.occupancyAt({12.25, -3.25, 0.25}));
  EXPECT_GT(whole.occupancyAt({12.25, 3.25, 0.25}), 0.5);  // the wall, still in the original
}

TEST(MapConfigValidation, RejectsBadValues) {
  MapConfig c;
  EXPECT_EQ(validate(c), "");
  c.voxel_size = -1.0;
  EXPECT_NE(validate(c).find("voxel_size"), std::string::npos);
  EXPECT_THROW(SemanticOccupancyMap{c}, std::invalid_argument);
  c = MapConfig{};
  c.p_miss = 0.7;
  EXPECT_NE(validate(c).find("p_miss"), std::string::npos);
}

}  // namespace
}  // namespace socc::map
