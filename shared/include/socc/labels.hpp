#pragma once
// Semantic classes: the 20 classes of the paper (SemanticKITTI learning map),
// class 0 = unlabeled. Raw SemanticKITTI ids are mapped here and nowhere else.
#include <array>
#include <cstdint>
#include <string_view>

namespace socc {

inline constexpr int kNumClasses = 20;  // K + 1, class 0 = unlabeled

enum Class : std::uint8_t {
  kUnlabeled = 0,
  kCar = 1,
  kBicycle = 2,
  kMotorcycle = 3,
  kTruck = 4,
  kOtherVehicle = 5,
  kPerson = 6,
  kBicyclist = 7,
  kMotorcyclist = 8,
  kRoad = 9,
  kParking = 10,
  kSidewalk = 11,
  kOtherGround = 12,
  kBuilding = 13,
  kFence = 14,
  kVegetation = 15,
  kTrunk = 16,
  kTerrain = 17,
  kPole = 18,
  kTrafficSign = 19,
};

struct Rgb {
  std::uint8_t r, g, b;
};

/// Maps a raw SemanticKITTI label (lower 16 bits of a .label entry) to 0..19.
/// Unknown raw ids map to kUnlabeled.
std::uint8_t mapSemanticKittiLabel(std::uint32_t raw_label);

/// Inverse representative raw id of a class (used when writing SemanticKITTI labels).
std::uint16_t semanticKittiRawId(std::uint8_t cls);

std::string_view className(std::uint8_t cls);
Rgb classColor(std::uint8_t cls);

inline bool isValidClass(int cls) { return cls >= 0 && cls < kNumClasses; }
/// person, bicyclist, motorcyclist: removed by semantic downsampling.
inline bool isHuman(std::uint8_t c) { return c == kPerson || c == kBicyclist || c == kMotorcyclist; }
inline bool isPoleOrSign(std::uint8_t c) { return c == kPole || c == kTrafficSign; }
/// road, parking, sidewalk, terrain (paper, Sec. semantic-aware downsampling).
inline bool isGround(std::uint8_t c) {
  return c == kRoad || c == kParking || c == kSidewalk || c == kTerrain;
}
/// Vehicles and humans: may move, so their voxels decay faster (p_miss_moving).
inline bool isPotentiallyMoving(std::uint8_t c) { return c >= kCar && c <= kMotorcyclist; }

}  // namespace socc
