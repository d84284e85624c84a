// Integration must not depend on thread scheduling: the same scans integrated with one
// thread and with two give byte-identical chunk answers (the misses are applied in parallel).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/kitti_io.hpp"
#include "test_helpers.hpp"

namespace socc::map {
namespace {

namespace fs = std::filesystem;

struct Scan {
  Eigen::Isometry3d pose;
  LabeledCloud cloud;
};

/// Everything a client can observe, encoded: results, stats and all chunk fields (occupied
/// at two thresholds, free list) of the whole scanned region.
std::vector<std::uint8_t> observe(const std::vector<Scan>& scans, int threads, double radius) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  SemanticOccupancyMap map{MapConfig{}};
  std::vector<std::uint8_t> bytes;
  const auto appendValue = [&bytes](std::int64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  for (const Scan& scan : scans) {
    const IntegrationResult r = map.integrate(scan.pose, scan.cloud);
    for (const std::int64_t v : {std::int64_t{r.points_used}, std::int64_t{r.voxels_hit},
                                 std::int64_t{r.voxels_touched}, std::int64_t{r.voxels_freed}})
      appendValue(v);
  }
  const MapStats s = map.stats();
  for (const std::int64_t v : {s.num_voxels, s.num_occupied, s.num_free, s.num_blocks})
    appendValue(v);
  for (const double threshold : {0.5, 0.45}) {
    ChunkQuery q;
    q.center = scans.front().pose.translation();
    q.radius = radius;
    q.occupancy_threshold = threshold;
    q.fields = chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS |
               chunk_request_t::FIELD_FREE | chunk_request_t::FIELD_INDEX;
    chunk_reply_t reply = service::queryChunkReply(map, q);
    reply.map_epoch = 0;  // random per map instance, by design
    EXPECT_GT(reply.num_voxels, 0);
    if (threshold == 0.5) {
      EXPECT_GT(reply.n_free, 0);
    }
    const int size = reply.getEncodedSize();
    const std::size_t at = bytes.size();
    bytes.resize(at + static_cast<std::size_t>(size));
    EXPECT_EQ(reply.encode(bytes.data() + at, 0, size), size);
  }
  return bytes;
}

/// Index of the first differing byte (or the shorter size); -1 when identical. Comparing
/// megabytes with EXPECT_EQ would print them all.
std::ptrdiff_t firstDifference(const std::vector<std::uint8_t>& a,
                               const std::vector<std::uint8_t>& b) {
  const auto [ia, ib] = std::mismatch(a.begin(), a.end(), b.begin(), b.end());
  if (ia == a.end() && ib == b.end()) return -1;
  return ia - a.begin();
}

TEST(Determinism, SyntheticScansGiveIdenticalMapsWithOneOrTwoThreads) {
  // A moving labeled wall (frees voxels and drops statistics) plus random clutter, seen from
  // a moving sensor, including points beyond max range.
  std::vector<Scan> scans;
  for (int i = 0; i < 6; ++i) {
    Scan scan;
    scan.pose = Eigen::Isometry3d::Identity();
    scan.pose.translation() = Eigen::Vector3d(0.3 * i, 0.1 * i, 0.0);
    scan.cloud = test::wall(8.0 + i, 6.0, 0.2, i % 2 == 0 ? kCar : kBuilding);
    test::append(scan.cloud, test::randomCloud(3000, 15.0, 7u + static_cast<std::uint32_t>(i)));
    test::append(scan.cloud, test::wall(150.0, 10.0, 1.0, kVegetation));
    scans.push_back(std::move(scan));
  }
  const std::vector<std::uint8_t> one = observe(scans, 1, 60.0);
  EXPECT_EQ(firstDifference(one, observe(scans, 2, 60.0)), -1);
  EXPECT_EQ(firstDifference(one, observe(scans, 2, 60.0)), -1);
}

TEST(Determinism, KittiScansGiveIdenticalMapsWithOneOrTwoThreads) {
  const fs::path root = fs::path(SOCC_SHARED_DATA_DIR) / "kitti_00_first16";
  if (!fs::exists(root)) GTEST_SKIP() << "shared data not found: " << root;
  const KittiSequence seq = listKittiSequence(root);
  ASSERT_GE(seq.scans.size(), 3u);
  const Poses poses = readKittiLidarPoses(root);
  std::vector<Scan> scans;
  for (std::size_t frame = 0; frame < 3; ++frame) {
    Scan scan{poses[frame], {}};
    scan.cloud.points = readKittiBin(seq.scans[frame]);
    if (frame == 0) {
      for (const std::uint32_t raw : readSemanticKittiLabels(root / "labels/000000.label"))
        scan.cloud.labels.push_back(mapSemanticKittiLabel(raw & 0xFFFFu));
    }
    scans.push_back(std::move(scan));
  }
  EXPECT_EQ(firstDifference(observe(scans, 1, 100.0), observe(scans, 2, 100.0)), -1);
}

}  // namespace
}  // namespace socc::map
