// Snapshots, exports (OctoMap, PCD), rendering and YAML configs.
#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <filesystem>
#include <fstream>

#include "../temp_dir.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/render_request_t.hpp"
#include "test_helpers.hpp"

namespace socc::map {
namespace {

namespace fs = std::filesystem;
using test::query;

using socc::testing::TempDir;

SemanticOccupancyMap sampleMap() {
  MapConfig cfg;
  cfg.voxel_size = 0.4;
  SemanticOccupancyMap map(cfg);
  for (int i = 0; i < 4; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = 0.5 * i;
    LabeledCloud c = test::randomCloud(3000, 8.0, 10 + i);
    test::append(c, test::wall(9.0, 3.0, 0.1, kBuilding));
    map.integrate(pose, c);
  }
  return map;
}

chunk_reply_t everything(const SemanticOccupancyMap& map) {
  ChunkQuery q;
  q.radius = 1000.0;
  q.fields = chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS |
             chunk_request_t::FIELD_INDEX | chunk_request_t::FIELD_FREE;
  chunk_reply_t reply = query(map, q);
  reply.map_epoch = 0;  // random per map instance, by design
  return reply;
}

std::vector<std::uint8_t> encode(const chunk_reply_t& r) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(r.getEncodedSize()));
  r.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

TEST(Snapshot, RoundTripIsExact) {
  TempDir dir;
  const SemanticOccupancyMap map = sampleMap();
  map.save(dir / "map.socc", "robots: 2");
  std::string meta;
  const SemanticOccupancyMap loaded = SemanticOccupancyMap::load(dir / "map.socc", &meta);
  EXPECT_EQ(meta, "robots: 2");
  EXPECT_EQ(loaded.version(), map.version());
  EXPECT_EQ(loaded.config().voxel_size, 0.4);
  const MapStats a = map.stats(), b = loaded.stats();
  EXPECT_EQ(a.num_voxels, b.num_voxels);
  EXPECT_EQ(a.num_occupied, b.num_occupied);
  EXPECT_EQ(a.num_blocks, b.num_blocks);
  EXPECT_EQ(encode(everything(map)), encode(everything(loaded)));  // bit-identical answers
  // No temp file left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "")) ++files;
  EXPECT_EQ(files, 1);
}

/// The answers of queryChunk that describe voxel content (no map epoch or version).
std::vector<std::vector<double>> content(const SemanticOccupancyMap& map) {
  ChunkQuery q;
  q.radius = 1000.0;
  q.fields = ChunkQuery::kFeatures | ChunkQuery::kStats | ChunkQuery::kIndex | ChunkQuery::kFree;
  const ChunkVoxels v = map.queryChunk(q);
  std::vector<std::vector<double>> rows;
  const auto add = [&rows](const auto& row) { rows.emplace_back(row.begin(), row.end()); };
  for (const auto& r : v.index) add(r);
  for (const auto& r : v.free_index) add(r);
  for (const auto& r : v.mean) add(r);
  for (const auto& r : v.covariance) add(r);
  for (const auto& r : v.class_prob) add(r);
  add(v.log_odds);
  add(v.count);
  add(v.label);
  add(v.occupancy);
  return rows;
}

// Integration after a load continues as in the map that was saved: the blocks' cached miss
// classes (not in the file) are recomputed from the loaded statistics.
TEST(Snapshot, IntegrationAfterLoadMatchesTheSavedMap) {
  TempDir dir;
  SemanticOccupancyMap map = sampleMap();
  map.save(dir / "map.socc");
  SemanticOccupancyMap loaded = SemanticOccupancyMap::load(dir / "map.socc");
  for (int i = 0; i < 3; ++i) {  // a moving car seen through, then a wall of another class
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() << -1.0 - 0.5 * i, 0.3 * i, 0.0;
    LabeledCloud c = test::wall(12.0 + i, 4.0, 0.15, i == 1 ? kCar : kVegetation);
    test::append(c, test::randomCloud(2000, 10.0, 40 + i));
    const IntegrationResult a = map.integrate(pose, c), b = loaded.integrate(pose, c);
    EXPECT_EQ(a.voxels_touched, b.voxels_touched);
    EXPECT_EQ(a.voxels_freed, b.voxels_freed);
  }
  EXPECT_GT(map.stats().num_occupied, 0);
  EXPECT_EQ(map.stats().num_occupied, loaded.stats().num_occupied);
  EXPECT_EQ(content(map), content(loaded));
}

TEST(Snapshot, CorruptionIsDetected) {
  TempDir dir;
  const SemanticOccupancyMap map = sampleMap();
  map.save(dir / "map.socc");
  std::string bytes;
  {
    std::ifstream in(dir / "map.socc", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto writeVariant = [&](const std::string& data) {
    std::ofstream out(dir / "bad.socc", std::ios::binary | std::ios::trunc);
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
  };
  const auto expectError = [&](const std::string& fragment) {
    try {
      SemanticOccupancyMap::load(dir / "bad.socc");
      ADD_FAILURE() << "corrupt snapshot loaded";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  for (const std::size_t pos : {bytes.size() / 2, bytes.size() - 1, std::size_t{100}}) {
    std::string flipped = bytes;
    flipped[pos] = static_cast<char>(flipped[pos] ^ 0x10);
    writeVariant(flipped);
    expectError("checksum");
  }
  std::string header = bytes;
  header[12] ^= 1;  // reserved field: header checksum catches it
  writeVariant(header);
  expectError("header checksum");
  writeVariant(bytes.substr(0, bytes.size() - 7));
  expectError("size mismatch");
  writeVariant("not a map at all, definitely not a map");
  expectError("bad magic");
  writeVariant("");
  expectError("too short");
  EXPECT_THROW(SemanticOccupancyMap::load(dir / "missing.socc"), std::runtime_error);

  // A failed load leaves an existing map untouched.
  SemanticOccupancyMap current = sampleMap();
  const auto before = encode(everything(current));
  try {
    current = SemanticOccupancyMap::load(dir / "bad.socc");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(encode(everything(current)), before);
}

TEST(Snapshot, UnwritableTargetThrows) {
  const SemanticOccupancyMap map = sampleMap();
  EXPECT_THROW(map.save("/nonexistent_dir_socc/map.socc"), std::runtime_error);
}

TEST(Export, OctomapBinaryHasTheOccupiedVoxels) {
  TempDir dir;
  const SemanticOccupancyMap map = sampleMap();
  const std::int64_t n = map.exportOctomap(dir / "map.bt", 0.5);
  EXPECT_EQ(n, map.stats().num_occupied);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary((dir / "map.bt").string()));
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.4);
  std::int64_t occupied_leaves = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
    if (tree.isNodeOccupied(*it)) ++occupied_leaves;
  EXPECT_GE(occupied_leaves, 1);  // binary trees prune: count the occupied voxels by lookup
  const chunk_reply_t r = everything(map);
  for (int i = 0; i < r.num_voxels; ++i) {
    const octomap::point3d p((r.index[0][i] + 0.5f) * 0.4f, (r.index[1][i] + 0.5f) * 0.4f,
                             (r.index[2][i] + 0.5f) * 0.4f);
    const octomap::OcTreeNode* node = tree.search(p);
    ASSERT_NE(node, nullptr);
    EXPECT_TRUE(tree.isNodeOccupied(node));
  }
  EXPECT_GT(map.exportOctomap(dir / "map.ot", 0.5), 0);
  std::unique_ptr<octomap::AbstractOcTree> ot(
      octomap::AbstractOcTree::read((dir / "map.ot").string()));
  ASSERT_NE(ot, nullptr);
  EXPECT_EQ(ot->getTreeType(), "ColorOcTree");
  EXPECT_THROW(map.exportOctomap(dir / "map.xyz", 0.5), std::runtime_error);
}

TEST(Export, PcdReadBackByPcl) {
  TempDir dir;
  const SemanticOccupancyMap map = sampleMap();
  const std::int64_t n = map.exportPcd(dir / "map.pcd", 0.5);
  pcl::PointCloud<pcl::PointXYZRGBL> cloud;
  ASSERT_EQ(pcl::io::loadPCDFile((dir / "map.pcd").string(), cloud), 0);
  EXPECT_EQ(static_cast<std::int64_t>(cloud.size()), n);
  EXPECT_EQ(n, map.stats().num_occupied);
  bool building = false;
  for (const auto& p : cloud.points)
    if (p.label == kBuilding) {
      building = true;
      const Rgb c = classColor(kBuilding);
      EXPECT_EQ(p.r, c.r);
      EXPECT_EQ(p.g, c.g);
      EXPECT_EQ(p.b, c.b);
    }
  EXPECT_TRUE(building);
}

TEST(Render, PngOfExpectedSize) {
  const SemanticOccupancyMap map = sampleMap();
  for (const int mode : {render_request_t::MODE_CLASS, render_request_t::MODE_OCCUPANCY,
                         render_request_t::MODE_HEIGHT}) {
    const auto img = map.render({-10, -5, -3}, {10, 5, 3}, 0.2, mode, 0.5);
    EXPECT_EQ(img.width, 100);
    EXPECT_EQ(img.height, 50);
    ASSERT_EQ(img.rgb.size(), 100u * 50u * 3u);
    const auto png = encodePng(img);
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png[1], 'P');
    EXPECT_EQ(png[2], 'N');
    EXPECT_EQ(png[3], 'G');
  }
  // The building wall at x = 9 is drawn in its class colour.
  const auto img =
      map.render({8.0, -1.0, -3}, {10.0, 1.0, 3}, 0.4, render_request_t::MODE_CLASS, 0.5);
  const Rgb c = classColor(kBuilding);
  int building = 0;
  for (std::size_t i = 0; i < img.rgb.size(); i += 3)
    building += img.rgb[i] == c.r && img.rgb[i + 1] == c.g && img.rgb[i + 2] == c.b;
  EXPECT_GT(building, 0);
  EXPECT_THROW(map.render({0, 0, 0}, {10000, 10, 1}, 0.5, 0, 0.5), std::invalid_argument);
  EXPECT_THROW(map.render({0, 0, 0}, {10, 10, 1}, 0.5, 7, 0.5), std::invalid_argument);
}

TEST(Config, YamlDefaultsAndErrors) {
  TempDir dir;
  const fs::path defaults = fs::path(SOCC_SOURCE_DIR) / "map_server/config/default.yaml";
  const MapConfig c = loadMapConfig(defaults);
  EXPECT_EQ(c.voxel_size, MapConfig{}.voxel_size);
  EXPECT_EQ(c.p_miss_moving, MapConfig{}.p_miss_moving);
  { std::ofstream(dir / "a.yaml") << "voxel_size: 0.25\nsemantics: false\n"; }
  const MapConfig a = loadMapConfig(dir / "a.yaml");
  EXPECT_EQ(a.voxel_size, 0.25);
  EXPECT_FALSE(a.semantics);
  const auto expectError = [&](const std::string& yaml, const std::string& fragment) {
    std::ofstream(dir / "b.yaml") << yaml;
    try {
      loadMapConfig(dir / "b.yaml");
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::string at = "map config " + (dir / "b.yaml").string() + ": ";
  expectError("voxel_sise: 0.5\n", at + "unknown key 'voxel_sise'");
  expectError("voxel_size: big\n", at + "key 'voxel_size': bad value 'big' (expected a number)");
  expectError("p_hit: 0.3\n", at + "p_hit must be in (0.5, 1)");
  expectError("max_points_per_scan: -5\n",
              at + "key 'max_points_per_scan': bad value '-5' (expected a non-negative integer)");
  expectError("max_points_per_scan: 0\n", at + "max_points_per_scan must be in [1, 1e8]");
  EXPECT_THROW(loadMapConfig(dir / "missing.yaml"), std::runtime_error);
}

}  // namespace
}  // namespace socc::map
