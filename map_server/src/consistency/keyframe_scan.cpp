#include "keyframe_scan.hpp"

#include <array>

#include "socc/labels.hpp"
#include "socc/odom/voxel_downsampling.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::consistency {

std::size_t KeyframeScan::bytes() const {
  std::size_t n = sizeof(KeyframeScan) + labels.capacity();
  for (const auto& row : xyz) n += row.capacity() * sizeof(std::int16_t);
  return n;
}

LabeledCloud KeyframeScan::cloud() const {
  LabeledCloud out;
  out.points = wire::pointsFromQuantized(xyz, resolution);
  out.labels = labels;
  return out;
}

KeyframeScan compactScan(const LabeledCloud& cloud, double voxel) {
  std::array<double, kNumClasses> every_class;
  every_class.fill(1.0);  // every class at the same grid: the map keeps them all
  // Every voxel gets a label (unlabeled when the cloud has none); times are not kept.
  const LabeledCloud down = odom::semanticVoxelDownsample(cloud, voxel, every_class);
  KeyframeScan out;
  out.resolution = wire::quantizePoints(down.points, out.xyz);
  out.labels = down.labels;
  return out;
}

}  // namespace socc::consistency
