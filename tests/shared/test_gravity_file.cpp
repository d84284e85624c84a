// gravity.txt: one "ux uy uz sigma_rad" line per frame; malformed lines are errors naming the
// file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../temp_dir.hpp"
#include "socc/gravity_file.hpp"

namespace fs = std::filesystem;

namespace socc {
namespace {

fs::path writeFile(const std::string& name, const std::string& text) {
  const fs::path file = socc::testing::processTempDir() / name;
  std::ofstream(file) << text;
  return file;
}

std::string errorOf(const fs::path& file) {
  try {
    readGravityFile(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(GravityFile, ReadsNormalizesAndSkipsSigmaZero) {
  const fs::path f =
      writeFile("good.txt", "0 0 1 0.0005\n0.0006 0 1.0004 1e-3\r\n0 0 0 0\n  0 1 0   0.2  \n");
  const auto g = readGravityFile(f);
  ASSERT_EQ(g.size(), 4u);
  ASSERT_TRUE(g[0]);
  EXPECT_EQ(g[0]->up, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(g[0]->sigma, 0.0005);
  ASSERT_TRUE(g[1]);
  EXPECT_NEAR(g[1]->up.norm(), 1.0, 1e-12);  // within the tolerance: normalized
  EXPECT_FALSE(g[2]);                        // sigma 0: no reference (the vector is not used)
  ASSERT_TRUE(g[3]);
  EXPECT_EQ(g[3]->up, Eigen::Vector3d::UnitY());
}

TEST(GravityFile, RoundTrip) {
  const std::vector<std::optional<GravityReference>> in = {
      GravityReference{Eigen::Vector3d(0.01, -0.02, 1.0).normalized(), 6e-4}, std::nullopt};
  const fs::path f = writeFile("round.txt", "");
  writeGravityFile(f, in);
  const auto out = readGravityFile(f);
  ASSERT_EQ(out.size(), 2u);
  ASSERT_TRUE(out[0]);
  EXPECT_LT((out[0]->up - in[0]->up).norm(), 1e-8);
  EXPECT_NEAR(out[0]->sigma, 6e-4, 1e-9);
  EXPECT_FALSE(out[1]);
}

TEST(GravityFile, MalformedLinesNameFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 0 1 0.001\n0 0 1\n", ":2: expected 4 numbers"},
      {"0 0 1 0.001 7\n", ":1: more than 4 values"},
      {"0 0 1 0.001\n\n", ":2: expected 4 numbers"},
      {"0 0 x 0.001\n", ":1: expected 4 numbers"},
      {"0 0 1 0.001\n0 0 1 0.001\n0 0 1 nan\n", ":3: non-finite"},
      {"0 0 inf 0.001\n", ":1: non-finite"},
      {"0 0 1 -0.001\n", ":1: negative sigma"},
      {"0 0 1.01 0.001\n", ":1: up vector of length"},
      {"0 0 0 0.001\n", ":1: up vector of length"},
  };
  int i = 0;
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    const fs::path f = writeFile("bad" + std::to_string(i++) + ".txt", text);
    const std::string error = errorOf(f);
    EXPECT_NE(error.find(f.string() + expected), std::string::npos) << error;
  }
  EXPECT_NE(errorOf("/nonexistent/gravity.txt").find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace socc
