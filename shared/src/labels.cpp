#include "socc/labels.hpp"

#include <array>

namespace socc {

namespace {

// One line per class, as the SemanticKITTI id table reads.
// clang-format off
constexpr std::uint8_t classOfRawId(std::uint32_t raw_id) {
  switch (raw_id) {
    case 10: case 252: return kCar;
    case 11: return kBicycle;
    case 15: return kMotorcycle;
    case 18: case 258: return kTruck;
    case 13: case 16: case 20: case 256: case 257: case 259: return kOtherVehicle;
    case 30: case 254: return kPerson;
    case 31: case 253: return kBicyclist;
    case 32: case 255: return kMotorcyclist;
    case 40: case 60: return kRoad;  // lane-marking counts as road
    case 44: return kParking;
    case 48: return kSidewalk;
    case 49: return kOtherGround;
    case 50: return kBuilding;
    case 51: return kFence;
    case 70: return kVegetation;
    case 71: return kTrunk;
    case 72: return kTerrain;
    case 80: return kPole;
    case 81: return kTrafficSign;
    default: return kUnlabeled;  // 0 unlabeled, 1 outlier, 52 other-structure, 99 other-object, unknown
  }
}
// clang-format on

// Raw ids in use end at 259. A table: label files are read per point, where the switch's
// jumps on mixed labels were mispredicted (~2 % of odom_client's CPU).
constexpr std::uint32_t kRawIds = 260;
constexpr std::array<std::uint8_t, kRawIds> kClassOfRawId = [] {
  std::array<std::uint8_t, kRawIds> table{};
  for (std::uint32_t id = 0; id < kRawIds; ++id) table[id] = classOfRawId(id);
  return table;
}();

}  // namespace

std::uint8_t mapSemanticKittiLabel(std::uint32_t raw_label) {
  const std::uint32_t id = raw_label & 0xFFFFu;
  return id < kRawIds ? kClassOfRawId[id] : std::uint8_t{kUnlabeled};
}

std::uint16_t semanticKittiRawId(std::uint8_t cls) {
  static constexpr std::array<std::uint16_t, kNumClasses> kRaw = {
      0, 10, 11, 15, 18, 20, 30, 31, 32, 40, 44, 48, 49, 50, 51, 70, 71, 72, 80, 81};
  return cls < kNumClasses ? kRaw[cls] : 0;
}

std::string_view className(std::uint8_t cls) {
  static constexpr std::array<std::string_view, kNumClasses> kNames = {
      "unlabeled", "car",          "bicycle", "motorcycle", "truck",    "other-vehicle", "person",
      "bicyclist", "motorcyclist", "road",    "parking",    "sidewalk", "other-ground",  "building",
      "fence",     "vegetation",   "trunk",   "terrain",    "pole",     "traffic-sign"};
  return cls < kNumClasses ? kNames[cls] : std::string_view("invalid");
}

Rgb classColor(std::uint8_t cls) {
  // SemanticKITTI colour map (RGB).
  static constexpr std::array<Rgb, kNumClasses> kColors = {
      {{0, 0, 0},       {100, 150, 245}, {100, 230, 245}, {30, 60, 150},   {80, 30, 180},
       {0, 0, 255},     {255, 30, 30},   {255, 40, 200},  {150, 30, 90},   {255, 0, 255},
       {255, 150, 255}, {75, 0, 75},     {175, 0, 75},    {255, 200, 0},   {255, 120, 50},
       {0, 175, 0},     {135, 60, 0},    {150, 240, 80},  {255, 240, 150}, {255, 0, 0}}};
  return cls < kNumClasses ? kColors[cls] : Rgb{128, 128, 128};
}

}  // namespace socc
