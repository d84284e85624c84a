#include <gtest/gtest.h>

#include <limits>

#include "socc/odom/preprocessing.hpp"

using socc::LabeledCloud;

TEST(Preprocessing, RangeFilterKeepsBandAndDropsNonFinite) {
  LabeledCloud c;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  c.points = {{1, 0, 0}, {10, 0, 0}, {0, 50, 0}, {200, 0, 0}, {nan, 10, 0}, {inf, 0, 0}, {0, 0, 6}};
  c.labels = {1, 2, 3, 4, 5, 6, 7};
  c.times = {0.f, 0.01f, 0.02f, 0.03f, 0.04f, 0.05f, nan};
  const LabeledCloud out = socc::odom::rangeFilter(c, 5.0, 100.0);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out.labels, (std::vector<std::uint8_t>{2, 3}));
  EXPECT_EQ(out.times, (std::vector<float>{0.01f, 0.02f}));
  EXPECT_TRUE(out.consistent());
}

TEST(Preprocessing, CheckCloudReportsSizesAndLabels) {
  LabeledCloud c;
  c.points = {{1, 2, 3}, {4, 5, 6}};
  EXPECT_TRUE(socc::odom::checkCloud(c).empty());
  c.labels = {1};
  EXPECT_NE(socc::odom::checkCloud(c).find("count"), std::string::npos);
  c.labels = {1, 20};
  EXPECT_NE(socc::odom::checkCloud(c).find("label 20"), std::string::npos);
  c.labels = {1, 19};
  EXPECT_TRUE(socc::odom::checkCloud(c).empty());
}

TEST(Preprocessing, DropLabelsMakesEverythingUnlabeled) {
  LabeledCloud c;
  c.points = {{1, 2, 3}, {4, 5, 6}};
  c.labels = {6, 13};
  socc::odom::dropLabels(c);
  EXPECT_EQ(c.labels, (std::vector<std::uint8_t>{0, 0}));
}
