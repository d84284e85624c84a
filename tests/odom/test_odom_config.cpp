#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "socc/odom/odom_config.hpp"

namespace fs = std::filesystem;
using socc::odom::OdomConfig;

namespace {
fs::path writeTemp(const std::string& name, const std::string& text) {
  const fs::path p =
      fs::temp_directory_path() / ("socc_odom_cfg_" + std::to_string(::getpid()) + name);
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(OdomConfig, DefaultsArePaperHyperparametersAndValid) {
  const OdomConfig c;
  EXPECT_TRUE(socc::odom::validate(c).empty());
  EXPECT_DOUBLE_EQ(c.gamma, 1.5);
  EXPECT_DOUBLE_EQ(c.w_lower, 0.25);
  EXPECT_DOUBLE_EQ(c.planarity_threshold, 0.1);
  EXPECT_DOUBLE_EQ(c.initial_threshold, 2.0);
  EXPECT_DOUBLE_EQ(c.min_motion, 0.1);
  const auto a = socc::odom::classFactors(c);
  EXPECT_EQ(a[socc::kPerson], 0.0);
  EXPECT_EQ(a[socc::kBicyclist], 0.0);
  EXPECT_EQ(a[socc::kMotorcyclist], 0.0);
  EXPECT_EQ(a[socc::kPole], 0.75);
  EXPECT_EQ(a[socc::kTrafficSign], 0.75);
  for (auto g : {socc::kRoad, socc::kParking, socc::kSidewalk, socc::kTerrain})
    EXPECT_EQ(a[g], 0.8);
  EXPECT_EQ(a[socc::kBuilding], 1.0);
  EXPECT_EQ(a[socc::kUnlabeled], 1.0);
}

TEST(OdomConfig, NoSemanticsMakesAllFactorsOne) {
  OdomConfig c;
  c.use_semantics = false;
  for (double a : socc::odom::classFactors(c)) EXPECT_EQ(a, 1.0);
}

TEST(OdomConfig, LoadsKnownKeys) {
  const fs::path p = writeTemp("ok.yaml", "max_range: 80\nmax_iterations: 20\ndeskew: false\n");
  const OdomConfig c = socc::odom::loadOdomConfig(p);
  EXPECT_DOUBLE_EQ(c.max_range, 80.0);
  EXPECT_EQ(c.max_iterations, 20);
  EXPECT_FALSE(c.deskew);
  fs::remove(p);
}

TEST(OdomConfig, DefaultYamlOfTheRepoLoads) {
  const fs::path p = fs::path(SOCC_ODOM_CONFIG_DIR) / "default.yaml";
  const OdomConfig c = socc::odom::loadOdomConfig(p);  // every key documented there is known
  EXPECT_TRUE(socc::odom::validate(c).empty());
}

TEST(OdomConfig, KittiYamlCorrectsTheHdl64sElevation) {
  const OdomConfig c = socc::odom::loadOdomConfig(fs::path(SOCC_ODOM_CONFIG_DIR) / "kitti.yaml");
  EXPECT_DOUBLE_EQ(c.vertical_angle_correction_deg, 0.205);
  EXPECT_DOUBLE_EQ(OdomConfig{}.vertical_angle_correction_deg, 0.0);  // other sensors: as given
  EXPECT_TRUE(socc::odom::validate(c).empty());
}

TEST(OdomConfig, LaterFilesOverrideEarlierOnesAndOnlyTheResultIsValidated) {
  const fs::path dir(SOCC_ODOM_CONFIG_DIR);
  const OdomConfig c =
      socc::odom::loadOdomConfig(std::vector<fs::path>{dir / "kitti.yaml", dir / "baseline.yaml"});
  EXPECT_DOUBLE_EQ(c.vertical_angle_correction_deg, 0.205);  // the sensor's layer
  EXPECT_FALSE(c.point_to_plane);                            // the method's layer
  EXPECT_TRUE(c.sparse_point_pairs);
  EXPECT_FALSE(c.use_semantics);
  EXPECT_EQ(socc::odom::loadOdomConfig(std::vector<fs::path>{}).max_range, OdomConfig{}.max_range);

  // min_voxel_size above the default max_voxel_size is invalid alone; the next layer fixes it.
  const fs::path a = writeTemp("layer_a.yaml", "min_voxel_size: 5.0\n");
  const fs::path b = writeTemp("layer_b.yaml", "max_voxel_size: 6.0\ninitial_voxel_size: 5.5\n");
  const OdomConfig ab = socc::odom::loadOdomConfig(std::vector<fs::path>{a, b});
  EXPECT_DOUBLE_EQ(ab.min_voxel_size, 5.0);
  EXPECT_DOUBLE_EQ(ab.max_voxel_size, 6.0);
  // The same problem left by the last layer is reported, naming that file.
  try {
    socc::odom::loadOdomConfig(std::vector<fs::path>{dir / "kitti.yaml", a});
    ADD_FAILURE() << "an invalid result was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("layer_a.yaml"), std::string::npos) << e.what();
  }
  fs::remove(a);
  fs::remove(b);
}

TEST(OdomConfig, RejectsUnknownKeysWrongTypesAndBadValues) {
  const auto expectError = [](const std::string& text, const std::string& needle) {
    const fs::path p = writeTemp("bad.yaml", text);
    try {
      socc::odom::loadOdomConfig(p);
      ADD_FAILURE() << "no error for: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    fs::remove(p);
  };
  expectError("max_rang: 80\n", "unknown key 'max_rang'");
  expectError("max_range: far\n", "max_range");
  expectError("w_lower: 2\n", "w_lower");
  expectError("refine_threshold: -0.1\n", "refine_threshold");
  expectError("refine_initial_pose: maybe\n", "refine_initial_pose");
  expectError("vertical_angle_correction_deg: 90\n", "vertical_angle_correction_deg");
  expectError("min_range: 50\nmax_range: 10\n", "max_range");
  expectError("relocalize_scan_lead: 0.2\n", "relocalize_scan_lead");  // above the margin
  expectError("relocalize_scan_lead: 0\n", "relocalize_scan_lead");
  expectError("[1, 2]\n", "map");
  expectError("a: [\n", "YAML");
  EXPECT_THROW(socc::odom::loadOdomConfig("/nonexistent/odom.yaml"), std::runtime_error);
}
