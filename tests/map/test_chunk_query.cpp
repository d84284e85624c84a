// Chunk queries against brute force over all voxels of the map.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "socc/chunk_request_t.hpp"
#include "socc/wire_arrays.hpp"
#include "test_helpers.hpp"

namespace socc::map {
namespace {

using test::query;
using wire::column;
constexpr std::int32_t kAll =
    chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS | chunk_request_t::FIELD_INDEX;

struct Voxel {
  double p_occ;
  std::size_t row;  // row in the full reply
};
using Index = std::array<int, 3>;

class ChunkQueryTest : public ::testing::Test {
 protected:
  ChunkQueryTest() : map_(MapConfig{}) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> yaw(-3.0, 3.0);
    for (int i = 0; i < 6; ++i) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation() = Eigen::Vector3d(0.7 * i, -0.3 * i, 0.1 * i);
      pose.linear() = Eigen::AngleAxisd(yaw(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      map_.integrate(pose, test::randomCloud(4000, 12.0, 100 + i));
    }
    // Brute force: every observed voxel, occupied or not (threshold 0 and the free list).
    ChunkQuery all;
    all.shape = ChunkQuery::Shape::kBox;
    all.box_min = Eigen::Vector3d::Constant(-1e6);
    all.box_max = Eigen::Vector3d::Constant(1e6);
    all.occupancy_threshold = 0.0;
    all.fields = kAll;
    full_ = query(map_, all);
    EXPECT_EQ(full_.num_voxels, map_.stats().num_voxels);
    for (int i = 0; i < full_.num_voxels; ++i)
      voxels_[{full_.index[0][i], full_.index[1][i], full_.index[2][i]}] = {
          full_.occupancy[i] / 255.0, static_cast<std::size_t>(i)};
  }

  double pOcc(std::size_t row) const {
    return 1.0 / (1.0 + std::exp(-static_cast<double>(full_.log_odds[row])));
  }

  void check(const ChunkQuery& q) {
    const chunk_reply_t r = query(map_, q);
    const double vs = map_.config().voxel_size;
    std::map<Index, bool> expected;  // index -> occupied
    for (const auto& [idx, v] : voxels_) {
      const Eigen::Vector3d c = (Eigen::Vector3d(idx[0], idx[1], idx[2]).array() + 0.5) * vs;
      const bool in =
          q.shape == ChunkQuery::Shape::kSphere
              ? (c - q.center).norm() <= q.radius
              : (c.array() >= q.box_min.array()).all() && (c.array() <= q.box_max.array()).all();
      if (in) expected[idx] = pOcc(v.row) >= q.occupancy_threshold;
    }
    std::size_t n_occ = 0, n_free = 0;
    for (const auto& [idx, occ] : expected) (occ ? n_occ : n_free)++;
    ASSERT_EQ(static_cast<std::size_t>(r.num_voxels), n_occ);
    ASSERT_EQ(r.n_index, r.num_voxels);
    ASSERT_EQ(r.n_features, (q.fields & chunk_request_t::FIELD_FEATURES) ? r.num_voxels : 0);
    ASSERT_EQ(r.n_stats, (q.fields & chunk_request_t::FIELD_STATS) ? r.num_voxels : 0);
    ASSERT_EQ(r.n_free, (q.fields & chunk_request_t::FIELD_FREE) ? static_cast<int>(n_free) : 0);
    ASSERT_EQ(wire::checkArrays(r), "") << "every row has its count: encode() trusts them";
    EXPECT_FALSE(r.truncated);
    for (int i = 0; i < r.num_voxels; ++i) {
      const Index idx{r.index[0][i], r.index[1][i], r.index[2][i]};
      ASSERT_TRUE(expected.count(idx) && expected[idx]);
      const std::size_t row = voxels_.at(idx).row;
      if (q.fields & chunk_request_t::FIELD_STATS) {
        EXPECT_EQ(r.count[i], full_.count[row]);
        EXPECT_EQ(r.log_odds[i], full_.log_odds[row]);
        EXPECT_EQ(column(r.class_prob, i), column(full_.class_prob, row));
        EXPECT_EQ(column(r.mean, i), column(full_.mean, row));
        EXPECT_EQ(column(r.covariance, i), column(full_.covariance, row));
      }
      if (q.fields & chunk_request_t::FIELD_FEATURES) {
        EXPECT_EQ(column(r.first_point, i), column(full_.first_point, row));
        EXPECT_EQ(r.label[i], full_.label[row]);
        EXPECT_EQ(column(r.normal, i), column(full_.normal, row));
      }
    }
    for (int i = 0; i < r.n_free; ++i) {
      const Index idx{r.free_index[0][i], r.free_index[1][i], r.free_index[2][i]};
      ASSERT_TRUE(expected.count(idx) && !expected[idx]);
    }
  }

  SemanticOccupancyMap map_;
  chunk_reply_t full_{};
  std::map<Index, Voxel> voxels_;
};

TEST_F(ChunkQueryTest, SpheresMatchBruteForce) {
  ASSERT_GT(voxels_.size(), 1000u);
  for (const double radius : {0.0, 0.4, 3.0, 7.5, 40.0}) {
    for (const double thr : {0.5, 0.3, 0.6}) {
      ChunkQuery q;
      q.center = Eigen::Vector3d(1.3, -2.1, 0.7);
      q.radius = radius;
      q.occupancy_threshold = thr;
      q.fields = kAll | chunk_request_t::FIELD_FREE;
      check(q);
    }
  }
}

TEST_F(ChunkQueryTest, BoxesMatchBruteForce) {
  const std::int32_t field_sets[] = {
      chunk_request_t::FIELD_INDEX, chunk_request_t::FIELD_INDEX | chunk_request_t::FIELD_FEATURES,
      chunk_request_t::FIELD_INDEX | chunk_request_t::FIELD_STATS | chunk_request_t::FIELD_FREE};
  for (const auto fields : field_sets) {
    ChunkQuery q;
    q.shape = ChunkQuery::Shape::kBox;
    q.box_min = Eigen::Vector3d(-5.2, -3.0, -1.1);
    q.box_max = Eigen::Vector3d(4.1, 6.0, 2.3);
    q.fields = fields;
    check(q);
    q.box_min = Eigen::Vector3d(-100, -100, -100);  // larger than the map: map-scan path
    q.box_max = Eigen::Vector3d(100, 100, 100);
    check(q);
  }
}

TEST_F(ChunkQueryTest, LimitTruncates) {
  ChunkQuery q;
  q.radius = 50.0;
  q.fields = kAll | chunk_request_t::FIELD_FREE;
  q.limit = 10;
  const chunk_reply_t r = query(map_, q);
  EXPECT_EQ(r.num_voxels, 10);
  EXPECT_EQ(r.n_features, 10);
  EXPECT_EQ(r.n_stats, 10);
  EXPECT_EQ(r.n_free, 10);
  EXPECT_EQ(r.num_classes, kNumClasses);
  EXPECT_TRUE(r.truncated);
  q.limit = 0;
  const chunk_reply_t all = query(map_, q);
  EXPECT_FALSE(all.truncated);
  EXPECT_GT(all.num_voxels, 10);
  // The limited answer is a prefix of the full one (deterministic order).
  for (int i = 0; i < 10; ++i) EXPECT_EQ(column(r.index, i), column(all.index, i));
}

TEST_F(ChunkQueryTest, NoStatsMeansNoClasses) {
  ChunkQuery q;
  q.radius = 5.0;
  q.fields = chunk_request_t::FIELD_FEATURES;
  const chunk_reply_t r = query(map_, q);
  EXPECT_EQ(r.n_stats, 0);
  EXPECT_EQ(r.num_classes, 0);
  EXPECT_EQ(r.n_index, 0);
  EXPECT_EQ(r.fields, chunk_request_t::FIELD_FEATURES);
  for (int i = 0; i < r.n_features; ++i) EXPECT_GE(r.occupancy[i], 128);
}

TEST_F(ChunkQueryTest, RejectsBadQueries) {
  ChunkQuery q;
  q.radius = std::nan("");
  EXPECT_THROW(map_.queryChunk(q), std::invalid_argument);
  q.radius = 1.0;
  q.occupancy_threshold = 2.0;
  EXPECT_THROW(map_.queryChunk(q), std::invalid_argument);
  q = ChunkQuery{};
  q.shape = ChunkQuery::Shape::kBox;
  q.box_min = Eigen::Vector3d(1, 1, 1);
  EXPECT_THROW(map_.queryChunk(q), std::invalid_argument);
}

}  // namespace
}  // namespace socc::map
