// Real data: KITTI 00 frames 0-2 with GT poses and the SemanticKITTI labels of frame 0.
#include <gtest/gtest.h>

#include <filesystem>

#include "service/chunk_reply.hpp"
#include "socc/chunk_features.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::map {
namespace {

namespace fs = std::filesystem;

TEST(KittiMap, RoadVoxelsArePlanarWithVerticalNormals) {
  const fs::path root = fs::path(SOCC_SHARED_DATA_DIR) / "kitti_00_first16";
  if (!fs::exists(root)) GTEST_SKIP() << "shared data not found: " << root;
  const KittiSequence seq = listKittiSequence(root);
  ASSERT_GE(seq.scans.size(), 3u);
  const Poses poses = readKittiLidarPoses(root);
  SemanticOccupancyMap map{MapConfig{}};
  for (int frame = 0; frame < 3; ++frame) {
    LabeledCloud cloud;
    cloud.points = readKittiBin(seq.scans[frame]);
    if (frame == 0) {
      for (const std::uint32_t raw : readSemanticKittiLabels(root / "labels/000000.label"))
        cloud.labels.push_back(mapSemanticKittiLabel(raw & 0xFFFFu));
    }
    ASSERT_EQ(map.validate(poses[frame], cloud), "");
    const IntegrationResult r = map.integrate(poses[frame], cloud);
    EXPECT_GT(r.voxels_hit, 10000);
  }
  ChunkQuery q;
  q.center = poses[0].translation();
  q.radius = 40.0;
  q.fields = chunk_request_t::FIELD_FEATURES;
  const chunk_reply_t r = service::queryChunkReply(map, q);
  int road = 0, with_features = 0, planar = 0, vertical = 0;
  for (int i = 0; i < r.num_voxels; ++i) {
    if (r.label[i] != kRoad) continue;
    ++road;
    const double tau = chunk::decodePlanarity(r.planarity[i]);
    if (tau < 0.0) continue;
    ++with_features;
    planar += tau < 0.1;
    vertical += std::abs(chunk::decodeNormal(r.normal[0][i], r.normal[1][i]).z()) > 0.9;
  }
  EXPECT_GT(road, 200);
  ASSERT_GT(with_features, 100);
  EXPECT_GT(planar, 0.7 * with_features) << planar << " of " << with_features;
  EXPECT_GT(vertical, 0.8 * with_features) << vertical << " of " << with_features;
}

}  // namespace
}  // namespace socc::map
