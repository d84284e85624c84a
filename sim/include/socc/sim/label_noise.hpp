#pragma once
// Semantic labels as a single-scan segmentation network gives them: wrong at object boundaries
// (the range-image networks' label bleeding across depth edges), commonly confused classes in
// blobs (road/sidewalk/terrain, vegetation/terrain/trunk, building/fence, pole/sign, car/truck),
// and no moving-object classes. LabelScore measures the mIoU this gives against the exact labels.
#include <array>
#include <cstdint>
#include <vector>

#include "socc/labels.hpp"
#include "socc/sim/realism.hpp"

namespace socc::sim {

/// The class a network most often outputs instead of `cls` (the second choice when `second`).
std::uint8_t confusedClass(std::uint8_t cls, bool second);

/// The raw id a single-scan network would give a point of raw id `raw` (moving -> static).
std::uint16_t singleScanRawId(std::uint16_t raw);

/// Intersection over union per class of predicted against exact labels (19 classes).
class LabelScore {
 public:
  void add(std::uint32_t exact_raw, std::uint32_t predicted_raw);
  void add(const std::vector<std::uint32_t>& exact, const std::vector<std::uint32_t>& predicted);
  /// Mean IoU [0, 1] over the classes present in the exact labels; 1 when there are none.
  double meanIou() const;
  int classesPresent() const;

 private:
  std::array<std::array<std::uint64_t, kNumClasses>, kNumClasses> counts_{};  // [exact][pred]
};

}  // namespace socc::sim
