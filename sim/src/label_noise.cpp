#include "socc/sim/label_noise.hpp"

#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

std::uint8_t confusedClass(std::uint8_t cls, bool second) {
  switch (cls) {
    case kCar:
      return second ? kOtherVehicle : kTruck;
    case kPerson:
      return second ? kBicyclist : kPole;
    case kRoad:
      return second ? kParking : kSidewalk;
    case kSidewalk:
      return second ? kTerrain : kRoad;
    case kOtherGround:
      return second ? kRoad : kSidewalk;
    case kBuilding:
      return second ? kVegetation : kFence;
    case kFence:
      return second ? kVegetation : kBuilding;
    case kVegetation:
      return second ? kTrunk : kTerrain;
    case kTrunk:
      return second ? kPole : kVegetation;
    case kTerrain:
      return second ? kSidewalk : kVegetation;
    case kPole:
      return second ? kTrafficSign : kTrunk;
    case kTrafficSign:
      return second ? kBuilding : kPole;
    default:
      return cls;
  }
}

std::uint16_t singleScanRawId(std::uint16_t raw_id) {
  switch (raw_id) {
    case raw::kMovingCar:
      return raw::kCar;
    case raw::kMovingPerson:
      return raw::kPerson;
    default:
      return raw_id;
  }
}

void LabelScore::add(std::uint32_t exact_raw, std::uint32_t predicted_raw) {
  ++counts_[mapSemanticKittiLabel(exact_raw)][mapSemanticKittiLabel(predicted_raw)];
}

void LabelScore::add(const std::vector<std::uint32_t>& exact,
                     const std::vector<std::uint32_t>& predicted) {
  for (std::size_t i = 0; i < exact.size() && i < predicted.size(); ++i)
    add(exact[i], predicted[i]);
}

int LabelScore::classesPresent() const {
  int n = 0;
  for (std::size_t c = 1; c < kNumClasses; ++c) {
    std::uint64_t row = 0;
    for (const auto v : counts_[c]) row += v;
    n += row > 0 ? 1 : 0;
  }
  return n;
}

double LabelScore::meanIou() const {
  double sum = 0.0;
  int n = 0;
  for (std::size_t c = 1; c < kNumClasses; ++c) {  // class 0 (unlabeled) is not scored
    std::uint64_t row = 0;
    std::uint64_t column = 0;
    for (std::size_t o = 0; o < kNumClasses; ++o) {
      row += counts_[c][o];
      column += counts_[o][c];
    }
    if (row == 0) continue;
    const std::uint64_t hit = counts_[c][c];
    sum += static_cast<double>(hit) / static_cast<double>(row + column - hit);
    ++n;
  }
  return n == 0 ? 1.0 : sum / n;
}

}  // namespace socc::sim
