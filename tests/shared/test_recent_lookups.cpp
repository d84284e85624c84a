// RecentLookups: a remembered key gives its value back, an unknown one nothing, and a key hashed
// to the same entry replaces it (the memo forgets, the table behind it answers).
#include <gtest/gtest.h>

#include "socc/recent_lookups.hpp"
#include "socc/voxel.hpp"

using socc::RecentLookups;
using socc::VoxelIndex;
using socc::VoxelIndexHash;

TEST(RecentLookups, RemembersUntilAKeyOfTheSameEntryReplacesIt) {
  RecentLookups<VoxelIndex, std::uint32_t, VoxelIndexHash, 4> recent;
  const VoxelIndex a(1, 2, 3);
  EXPECT_EQ(recent.find(a), nullptr);
  recent.remember(a, 7);
  ASSERT_NE(recent.find(a), nullptr);
  EXPECT_EQ(*recent.find(a), 7u);
  // Some other key lands in a's entry (4 entries): a is forgotten, the other found.
  VoxelIndex other(0, 0, 0);
  for (int x = 2; VoxelIndexHash{}(other) % 4 != VoxelIndexHash{}(a) % 4 || other == a; ++x)
    other = VoxelIndex(x, 0, 0);
  recent.remember(other, 9);
  EXPECT_EQ(recent.find(a), nullptr);
  ASSERT_NE(recent.find(other), nullptr);
  EXPECT_EQ(*recent.find(other), 9u);
  // 0 is a value like any other (not "unused").
  recent.remember(a, 0);
  ASSERT_NE(recent.find(a), nullptr);
  EXPECT_EQ(*recent.find(a), 0u);
}
