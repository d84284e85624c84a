#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../temp_dir.hpp"
#include "socc/yaml_fields.hpp"

namespace fs = std::filesystem;

namespace socc {
namespace {

// One variable of each kind the table binds, with defaults to see what the file left alone.
struct Vars {
  bool flag = true;
  int count = 3;
  std::int64_t big = 7;
  std::size_t size = 9;
  double ratio = 0.5;
  std::string name = "default";
  std::optional<std::string> path;
  double inner = 1.0;
  YamlFields section{{"inner", &inner}};
  YamlFields fields() {
    return {{"flag", &flag},   {"count", &count}, {"big", &big},   {"size", &size},
            {"ratio", &ratio}, {"name", &name},   {"path", &path}, {"section", &section}};
  }
};

fs::path write(const std::string& text) {
  const fs::path p = socc::testing::processTempDir() / "config.yaml";
  std::ofstream(p) << text;
  return p;
}

// The message of the load's error ("" when it loaded).
std::string error(const std::string& text, const std::function<std::string()>& validate = {}) {
  Vars v;
  try {
    loadYamlFields(write(text), "test config", v.fields(), validate);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(YamlFields, SetsEveryKindAndKeepsDefaults) {
  Vars v;
  loadYamlFields(write("flag: false\ncount: -4\nbig: 5000000000\nsize: 12\nratio: 1e-3\n"
                       "name: grid\npath: maps/a.yaml\nsection:\n  inner: 2.5\n"),
                 "test config", v.fields());
  EXPECT_FALSE(v.flag);
  EXPECT_EQ(v.count, -4);
  EXPECT_EQ(v.big, 5'000'000'000);
  EXPECT_EQ(v.size, 12u);
  EXPECT_DOUBLE_EQ(v.ratio, 1e-3);
  EXPECT_EQ(v.name, "grid");
  EXPECT_EQ(v.path, "maps/a.yaml");
  EXPECT_DOUBLE_EQ(v.inner, 2.5);

  Vars d;
  loadYamlFields(write("count: 8\n"), "test config", d.fields());
  EXPECT_EQ(d.count, 8);
  EXPECT_TRUE(d.flag);
  EXPECT_EQ(d.name, "default");
  EXPECT_FALSE(d.path.has_value());  // absent, unlike an empty string
}

TEST(YamlFields, EmptyFileKeepsDefaultsButIsValidated) {
  EXPECT_EQ(error(""), "");
  EXPECT_EQ(error("# only a comment\n"), "");
  const fs::path p = write("");
  EXPECT_EQ(error("", [] { return "count must be > 5"; }),
            "test config " + p.string() + ": count must be > 5");
}

TEST(YamlFields, ErrorTexts) {
  const std::string at = "test config " + write("").string() + ": ";
  EXPECT_EQ(error("cout: 1\n"), at + "unknown key 'cout'");
  EXPECT_EQ(error("section:\n  outer: 1\n"), at + "unknown key 'section.outer'");
  EXPECT_EQ(error("ratio: big\n"), at + "key 'ratio': bad value 'big' (expected a number)");
  EXPECT_EQ(error("count: 1.5\n"), at + "key 'count': bad value '1.5' (expected an integer)");
  EXPECT_EQ(error("size: -5\n"),
            at + "key 'size': bad value '-5' (expected a non-negative integer)");
  EXPECT_EQ(error("flag: maybe\n"), at + "key 'flag': bad value 'maybe' (expected true or false)");
  EXPECT_EQ(error("name: [a, b]\n"), at + "key 'name': bad value '<sequence>' (expected text)");
  EXPECT_EQ(error("ratio:\n"), at + "key 'ratio': bad value '<empty>' (expected a number)");
  EXPECT_EQ(error("section: 3\n"), at + "key 'section': bad value '3' (expected a mapping)");
  EXPECT_EQ(error("section:\n  inner: x\n"),
            at + "key 'section.inner': bad value 'x' (expected a number)");
  EXPECT_EQ(error("[1, 2]\n"), at + "expected a mapping of key: value");
  EXPECT_EQ(error("? [a]\n: 1\n"), at + "unknown key '<sequence>'");
  EXPECT_EQ(error("count: 1\ncout: 2\nratio: x\n"), at + "unknown key 'cout'");  // file order
  EXPECT_EQ(error("a: [\n").rfind(at + "not valid YAML: ", 0), 0u);
  Vars v;
  try {
    loadYamlFields("/nonexistent/x.yaml", "test config", v.fields());
    ADD_FAILURE() << "loaded a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "test config /nonexistent/x.yaml: cannot read the file");
  }
}

}  // namespace
}  // namespace socc
