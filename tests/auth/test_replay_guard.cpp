#include <gtest/gtest.h>

#include "socc/auth/replay_guard.hpp"

namespace socc::auth {
namespace {

TEST(ReplayGuard, PerClientStrictlyIncreasing) {
  ReplayGuard g;
  EXPECT_EQ(g.check("a", 5), CounterCheck::kFresh);
  g.accept("a", 5);
  EXPECT_EQ(g.check("a", 5), CounterCheck::kReplayed);
  EXPECT_EQ(g.check("a", 4), CounterCheck::kStale);
  EXPECT_EQ(g.check("a", 6), CounterCheck::kFresh);
  EXPECT_EQ(g.check("b", 1), CounterCheck::kFresh);
  g.accept("a", 3);  // never lowers
  EXPECT_EQ(g.counters().at("a"), 5);
}

TEST(ReplayGuard, ExportImportRoundTrip) {
  ReplayGuard g;
  g.accept("robot1", 1'700'000'000'000'000);
  g.accept("robot 2", -3);
  const std::string text = serializeCounters(g.counters());
  ReplayGuard restored;
  restored.accept("robot1", 10);
  restored.importCounters(parseCounters(text));
  EXPECT_EQ(restored.counters(), g.counters());
  EXPECT_EQ(restored.check("robot1", 1'700'000'000'000'000), CounterCheck::kReplayed);
}

TEST(ReplayGuard, ParseRejectsMalformedText) {
  EXPECT_THROW(parseCounters("12robot\n"), std::runtime_error);
  EXPECT_THROW(parseCounters("x robot\n"), std::runtime_error);
  EXPECT_THROW(parseCounters("99999999999999999999 robot\n"), std::runtime_error);
  EXPECT_TRUE(parseCounters("").empty());
  EXPECT_THROW(serializeCounters({{"bad\nid", 1}}), std::invalid_argument);
}

}  // namespace
}  // namespace socc::auth
