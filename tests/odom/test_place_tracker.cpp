// PlaceTracker (relocalization's confirmation rule, docs/relocalization.md): a place is accepted
// only after leading on consecutive scans by the margin on average (by scan_lead on each);
// rivals once found are followed by the odometry and keep counting against it.
#include <gtest/gtest.h>

#include "socc/odom/place_tracker.hpp"

namespace {

using namespace socc::odom;

Eigen::Isometry3d at(double x, double yaw = 0.0) {
  Eigen::Isometry3d p(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  p.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return p;
}

VerifiedPlace place(const Eigen::Isometry3d& pose, double fitness, double free = 0.0) {
  return {pose, fitness, free};
}

PlaceRules twoScans() {
  PlaceRules r;
  r.min_fitness = 0.5;
  r.margin = 0.1;
  r.confirm_scans = 2;
  r.scan_lead = 0.08;
  return r;
}

const Eigen::Isometry3d kStep = at(1.0);  // the robot's motion between scans: 1 m ahead

TEST(PlaceTracker, AcceptsAPlaceOnlyAfterItLedOnConsecutiveScans) {
  PlaceTracker tracker(twoScans());
  const Relocalization first = tracker.update(kStep, {place(at(10.0), 0.8)});
  EXPECT_FALSE(first.pose);
  EXPECT_EQ(first.confirmed, 1);
  // The next scan: the place moved on by the odometry, verified again.
  ASSERT_EQ(tracker.predicted(kStep).size(), 1u);
  EXPECT_NEAR(tracker.predicted(kStep)[0].translation().x(), 11.0, 1e-9);
  const Relocalization second = tracker.update(kStep, {place(at(11.02), 0.8)});
  ASSERT_TRUE(second.pose);
  EXPECT_EQ(second.confirmed, 2);
  EXPECT_NEAR(second.pose->translation().x(), 11.02, 1e-9);
}

TEST(PlaceTracker, ARivalWithinTheMarginResetsTheLead) {
  PlaceTracker tracker(twoScans());
  EXPECT_EQ(tracker.update(kStep, {place(at(10.0), 0.8)}).confirmed, 1);
  // A lookalike 30 m on, turned around, explains nearly as much: no place leads.
  const Relocalization tie =
      tracker.update(kStep, {place(at(11.0), 0.8), place(at(41.0, M_PI), 0.78)});
  EXPECT_FALSE(tie.pose);
  EXPECT_EQ(tie.confirmed, 0);
  EXPECT_NE(tie.problem.find("ambiguous"), std::string::npos);
  // Both are followed: the lookalike is verified again next time as a rival.
  EXPECT_EQ(tracker.predicted(kStep).size(), 2u);
  // It fades; the true place leads again, from one scan.
  const Relocalization after = tracker.update(kStep, {place(at(12.0), 0.8), place(at(42.0), 0.3)});
  EXPECT_FALSE(after.pose);
  EXPECT_EQ(after.confirmed, 1);
  EXPECT_TRUE(tracker.update(kStep, {place(at(13.0), 0.8)}).pose);
}

TEST(PlaceTracker, APlaceMissingOnAScanStartsOver) {
  PlaceTracker tracker(twoScans());
  tracker.update(kStep, {place(at(10.0), 0.8)});
  EXPECT_FALSE(tracker.update(kStep, {}).pose);
  EXPECT_EQ(tracker.size(), 0u);
  EXPECT_FALSE(tracker.update(kStep, {place(at(12.0), 0.8)}).pose);  // led on one scan only
}

// The realistic street, seed 3: a lookalike 232 m off, turned around, with no rival, explained
// 64-68 % of two stacked scans but put 20 % of them into free space, and was accepted. The share
// explained counts net of the share contradicted: 44 % does not lead.
TEST(PlaceTracker, ThePlaceMustExplainEnoughNetOfTheFreeSpaceItContradicts) {
  PlaceTracker tracker(twoScans());
  for (int scan = 0; scan < 3; ++scan) {
    const Relocalization r = tracker.update(kStep, {place(at(10.0 + scan), 0.64, 0.2)});
    EXPECT_FALSE(r.pose);
    EXPECT_EQ(r.confirmed, 0);
    EXPECT_NE(r.problem.find("net of the free space"), std::string::npos) << r.problem;
  }
  tracker.update(kStep, {place(at(20.0), 0.75, 0.2)});  // 55 % net: leads
  EXPECT_TRUE(tracker.update(kStep, {place(at(21.0), 0.75, 0.2)}).pose);
}

TEST(PlaceTracker, ALeadIsNotInheritedByAnotherPlace) {
  PlaceTracker tracker(twoScans());
  tracker.update(kStep, {place(at(10.0), 0.8)});
  // Where the odometry says the place went is 11 m; a place 5 m from there is another one.
  const Relocalization r = tracker.update(kStep, {place(at(16.0), 0.8)});
  EXPECT_FALSE(r.pose);
  EXPECT_EQ(r.confirmed, 1);
}

TEST(PlaceTracker, FreeSpaceCountsAgainstAPlaceAndTooLittleFitnessNeverLeads) {
  PlaceTracker tracker(twoScans());
  // Evidence: 0.9 - 0.3 = 0.6 against 0.63: the second place is ahead, by less than the floor.
  const Relocalization r =
      tracker.update(kStep, {place(at(10.0), 0.9, 0.3), place(at(50.0), 0.7, 0.07)});
  EXPECT_NEAR(r.evidence, 0.63, 1e-9);
  EXPECT_NEAR(r.runner_up, 0.6, 1e-9);
  EXPECT_EQ(r.confirmed, 0);  // less than scan_lead ahead
  PlaceTracker weak(twoScans());
  for (int k = 0; k < 4; ++k) {
    const Relocalization w = weak.update(kStep, {place(at(10.0 + k), 0.45)});
    EXPECT_FALSE(w.pose);
    EXPECT_EQ(w.confirmed, 0);
  }
}

// The realistic indoor room: its quarter-turn lookalike explains 89-91 % net against the true
// place's 98-100 % on every scan, never 10 points behind. Leads add up: taken at the third scan.
TEST(PlaceTracker, ASmallLeadOnEveryScanAddsUp) {
  PlaceTracker tracker(twoScans());
  for (int scan = 0; scan < 2; ++scan) {
    const Relocalization r =
        tracker.update(kStep, {place(at(10.0 + scan), 0.99), place(at(30.0 + scan, M_PI_2), 0.9)});
    EXPECT_FALSE(r.pose);
    EXPECT_EQ(r.confirmed, scan + 1);
    EXPECT_NE(r.problem.find("confirming"), std::string::npos) << r.problem;
  }
  const Relocalization third =
      tracker.update(kStep, {place(at(12.0), 0.99), place(at(32.0, M_PI_2), 0.9)});
  ASSERT_TRUE(third.pose);
  EXPECT_EQ(third.confirmed, 3);
  EXPECT_NEAR(third.lead, 0.27, 1e-9);
  // One scan less than scan_lead ahead starts the sum over.
  PlaceTracker reset(twoScans());
  reset.update(kStep, {place(at(10.0), 0.99), place(at(30.0), 0.9)});
  reset.update(kStep, {place(at(11.0), 0.99), place(at(31.0), 0.96)});
  EXPECT_FALSE(reset.update(kStep, {place(at(12.0), 0.99), place(at(32.0), 0.9)}).pose);
  EXPECT_FALSE(reset.update(kStep, {place(at(13.0), 0.99), place(at(33.0), 0.9)}).pose);
  EXPECT_TRUE(reset.update(kStep, {place(at(14.0), 0.99), place(at(34.0), 0.9)}).pose);
}

// bench_relocalization --elsewhere 2 (the rooms with other furniture): the quarter-turn lookalike
// explained 96 % with 7 % in free space against the true place's 84 %, scan after scan. At a
// floor of 0.05 it added up and was accepted; below scan_lead a lead never counts.
TEST(PlaceTracker, AFaintLeadNeverAddsUpHoweverLongItLasts) {
  PlaceTracker tracker(twoScans());
  for (int scan = 0; scan < 20; ++scan) {
    const Relocalization r = tracker.update(
        kStep, {place(at(10.0 + scan, M_PI_2), 0.96, 0.07), place(at(14.0 + scan), 0.84)});
    EXPECT_FALSE(r.pose);
    EXPECT_EQ(r.confirmed, 0);
  }
}

TEST(PlaceTracker, OneConfirmingScanAcceptsAtOnce) {
  PlaceRules rules = twoScans();
  rules.confirm_scans = 1;
  PlaceTracker tracker(rules);
  EXPECT_TRUE(tracker.update(kStep, {place(at(10.0), 0.8)}).pose);
}

}  // namespace
