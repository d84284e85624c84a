#include <gtest/gtest.h>

#include "socc/labels.hpp"

namespace socc {
namespace {

TEST(Labels, MapsSemanticKittiRawIds) {
  EXPECT_EQ(mapSemanticKittiLabel(0), kUnlabeled);
  EXPECT_EQ(mapSemanticKittiLabel(10), kCar);
  EXPECT_EQ(mapSemanticKittiLabel(252), kCar);  // moving-car
  EXPECT_EQ(mapSemanticKittiLabel(60), kRoad);  // lane-marking
  EXPECT_EQ(mapSemanticKittiLabel(81), kTrafficSign);
  EXPECT_EQ(mapSemanticKittiLabel(254), kPerson);
  EXPECT_EQ(mapSemanticKittiLabel(52), kUnlabeled);  // other-structure
  EXPECT_EQ(mapSemanticKittiLabel(12345), kUnlabeled);
  EXPECT_EQ(mapSemanticKittiLabel(259), kOtherVehicle);  // the last id of the table
  EXPECT_EQ(mapSemanticKittiLabel(260), kUnlabeled);     // the first past it
  // Upper 16 bits are the instance id.
  EXPECT_EQ(mapSemanticKittiLabel((7u << 16) | 50u), kBuilding);
}

TEST(Labels, RawIdRoundTrip) {
  for (int c = 0; c < kNumClasses; ++c)
    EXPECT_EQ(mapSemanticKittiLabel(semanticKittiRawId(static_cast<std::uint8_t>(c))), c);
}

TEST(Labels, Groups) {
  EXPECT_TRUE(isHuman(kPerson) && isHuman(kBicyclist) && isHuman(kMotorcyclist));
  EXPECT_FALSE(isHuman(kCar));
  EXPECT_TRUE(isGround(kRoad) && isGround(kTerrain) && !isGround(kOtherGround));
  EXPECT_TRUE(isPoleOrSign(kPole) && isPoleOrSign(kTrafficSign));
  EXPECT_TRUE(isPotentiallyMoving(kCar) && !isPotentiallyMoving(kBuilding));
  EXPECT_EQ(className(kVegetation), "vegetation");
}

}  // namespace
}  // namespace socc
