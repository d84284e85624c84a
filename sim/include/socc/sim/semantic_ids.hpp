#pragma once
// The raw SemanticKITTI label ids the simulator writes (lower 16 bits of a .label entry).
#include <cstdint>

namespace socc::sim::raw {

inline constexpr std::uint16_t kCar = 10;
inline constexpr std::uint16_t kPerson = 30;
inline constexpr std::uint16_t kRoad = 40;
inline constexpr std::uint16_t kSidewalk = 48;
inline constexpr std::uint16_t kOtherGround = 49;
inline constexpr std::uint16_t kBuilding = 50;
inline constexpr std::uint16_t kFence = 51;
inline constexpr std::uint16_t kOtherStructure = 52;
inline constexpr std::uint16_t kVegetation = 70;
inline constexpr std::uint16_t kTrunk = 71;
inline constexpr std::uint16_t kTerrain = 72;
inline constexpr std::uint16_t kPole = 80;
inline constexpr std::uint16_t kTrafficSign = 81;
inline constexpr std::uint16_t kOtherObject = 99;
inline constexpr std::uint16_t kMovingCar = 252;
inline constexpr std::uint16_t kMovingPerson = 254;

}  // namespace socc::sim::raw
