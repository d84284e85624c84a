#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "socc/eval/error_statistics.hpp"

namespace socc::eval {
namespace {

TEST(ErrorStatistics, HandComputed) {
  const ErrorStatistics s = computeStatistics({1.0, 2.0, 3.0, 4.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std, as numpy/evo
}

TEST(ErrorStatistics, OddMedian) {
  EXPECT_DOUBLE_EQ(computeStatistics({5, 1, 3}).median, 3.0);
}

TEST(ErrorStatistics, EmptyThrows) {
  EXPECT_THROW(computeStatistics({}), std::invalid_argument);
}

}  // namespace
}  // namespace socc::eval
