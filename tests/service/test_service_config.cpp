// loadServerConfig: the server.yaml keys (socc/yaml_fields.hpp), paths resolved beside the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "service/service_config.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

TEST(ServerConfig, RelativePathsResolveBesideTheFile) {
  test::TempDir dir;
  const auto server = dir.path() / "server.yaml";
  std::ofstream(dir.path() / "grid.yaml") << "voxel_size: 0.25\n";
  std::ofstream(server) << "map_config: grid.yaml\nkey_file: map.key\nfile_dir: maps\n"
                           "auth_queries: true\nlimits:\n  max_robots: 8\n";
  const ServerConfig c = loadServerConfig(server);
  EXPECT_EQ(c.map.voxel_size, 0.25);
  EXPECT_EQ(c.key_file, dir.path() / "map.key");
  EXPECT_EQ(c.file_dir, "maps");  // resolved by map_server against its working directory
  EXPECT_TRUE(c.auth_queries);
  EXPECT_EQ(c.limits.max_robots, 8);
  EXPECT_FALSE(c.consistency.enabled);  // off unless asked for (docs/consistency.md)

  std::ofstream(server) << "consistency:\n  enabled: true\n  keyframe_distance: 5\n";
  EXPECT_TRUE(loadServerConfig(server).consistency.enabled);
  EXPECT_EQ(loadServerConfig(server).consistency.keyframe_distance, 5.0);

  std::ofstream(server) << "key_file: /etc/socc/map.key\n";
  EXPECT_EQ(loadServerConfig(server).key_file, "/etc/socc/map.key");
  std::ofstream(server) << "";
  EXPECT_TRUE(loadServerConfig(server).key_file.empty());  // no key: unauthenticated
}

TEST(ServerConfig, ShippedFileStatesTheConsistencyDefaults) {
  const auto shipped = std::filesystem::path(__FILE__).parent_path() / "../../map_server/config";
  const consistency::ConsistencyParams defaults;
  const consistency::ConsistencyParams read = loadServerConfig(shipped / "server.yaml").consistency;
  EXPECT_EQ(read.enabled, defaults.enabled);
  EXPECT_EQ(read.keyframe_distance, defaults.keyframe_distance);
  EXPECT_EQ(read.keyframe_voxel, defaults.keyframe_voxel);
  EXPECT_EQ(read.min_loop_travel, defaults.min_loop_travel);
  EXPECT_EQ(read.search_radius, defaults.search_radius);
  EXPECT_EQ(read.drift_share, defaults.drift_share);
  EXPECT_EQ(read.max_descriptor_distance, defaults.max_descriptor_distance);
  EXPECT_EQ(read.scan_to_scan_edges, defaults.scan_to_scan_edges);
  EXPECT_EQ(read.snap_min_t, defaults.snap_min_t);
  EXPECT_EQ(read.snap_min_r, defaults.snap_min_r);
  EXPECT_EQ(read.correction_window, defaults.correction_window);
  EXPECT_EQ(read.rebuild_region, defaults.rebuild_region);
  EXPECT_EQ(read.rebuild_region_shift, defaults.rebuild_region_shift);
  EXPECT_EQ(read.rebuild_region_max_share, defaults.rebuild_region_max_share);
  EXPECT_EQ(read.gravity_priors, defaults.gravity_priors);
  EXPECT_EQ(read.gravity_sigma_floor, defaults.gravity_sigma_floor);
}

TEST(ServerConfig, ShippedFileStatesTheLocalizationBudget) {
  const auto shipped = std::filesystem::path(__FILE__).parent_path() / "../../map_server/config";
  const localization::SearchParams defaults;
  const localization::SearchParams read =
      loadServerConfig(shipped / "server.yaml").localization.search;
  EXPECT_EQ(read.max_iterations, defaults.max_iterations);
  EXPECT_EQ(read.max_inlier_tests, defaults.max_inlier_tests);
  EXPECT_EQ(read.correspondence_randomness, defaults.correspondence_randomness);
}

TEST(ServerConfig, ErrorsNameTheFileAndTheKey) {
  test::TempDir dir;
  const auto server = dir.path() / "server.yaml";
  const auto error = [&](const std::string& text) -> std::string {
    std::ofstream(server) << text;
    try {
      loadServerConfig(server);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string at = "server config " + server.string() + ": ";
  EXPECT_EQ(error("limits:\n  max_robots: 0\n"), at + "limits.max_robots must be > 0");
  EXPECT_EQ(error("plausibility:\n  linear_slack: -1\n"),
            at + "plausibility.linear_slack must be >= 0");
  EXPECT_EQ(error("limits:\n  robot_chunk_rate: -1\n"),
            at + "limits.robot_chunk_rate must be >= 0");
  EXPECT_EQ(error("limits:\n  robot_integrate_rate: 0\n"), "accepted");  // 0: no limit
  EXPECT_EQ(error("limits:\n  max_waiting_searches: -1\n"),
            at + "limits.max_waiting_searches must be >= 0");
  EXPECT_EQ(error("limits:\n  max_waiting_searches: 0\n"), "accepted");  // only the running one
  EXPECT_EQ(error("plausibility:\n  speed: 3\n"), at + "unknown key 'plausibility.speed'");
  EXPECT_EQ(error("consistency:\n  keyframe_distance: 0\n"),
            at + "consistency.keyframe_distance must be > 0");
  EXPECT_EQ(error("consistency:\n  max_descriptor_distance: 2\n"),
            at + "consistency.max_descriptor_distance must be in [0, 1]");
  EXPECT_EQ(error("consistency:\n  rebuild_region_max_share: 1.5\n"),
            at + "consistency.rebuild_region_max_share must be in [0, 1]");
  EXPECT_EQ(error("consistency:\n  gravity_sigma_floor: 0\n"),
            at + "consistency.gravity_sigma_floor must be > 0");
  EXPECT_EQ(error("localization:\n  max_draws: 0\n"), at + "localization.max_draws must be > 0");
  EXPECT_EQ(error("localization:\n  feature_candidates: 0\n"),
            at + "localization.feature_candidates must be > 0");
  EXPECT_EQ(error("localization:\n  max_draws: 5000\n  max_inlier_tests: 100000\n"), "accepted");
  EXPECT_EQ(error("limits:\n  max_robots: many\n"),
            at + "key 'limits.max_robots': bad value 'many' (expected an integer)");
  // The grid file reports its own name.
  std::ofstream(dir.path() / "grid.yaml") << "voxel_size: big\n";
  EXPECT_EQ(error("map_config: grid.yaml\n"),
            "map config " + (dir.path() / "grid.yaml").string() +
                ": key 'voxel_size': bad value 'big' (expected a number)");
}

}  // namespace
}  // namespace socc::service
