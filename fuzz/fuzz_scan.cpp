// scan_t as a subscriber (odometry client, tools) receives it: checked decode, then the map's
// validation and, when valid, integration into a small map.
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/rpc/safe_decode.hpp"
#include "socc/scan_t.hpp"
#include "socc/wire_arrays.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (64u << 20)) return 0;
  const auto scan = socc::rpc::safeDecode<socc::scan_t>(data, static_cast<int>(size));
  if (!scan) return 0;
  if (!socc::wire::checkArrays(*scan).empty()) __builtin_trap();  // decode() guarantees it
  socc::LabeledCloud cloud;
  cloud.points = socc::wire::pointsFromRows(scan->xyz);
  cloud.labels = scan->label;
  cloud.times = scan->time;
  socc::map::MapConfig config;
  config.voxel_size = 1.0;
  config.max_range = 30.0;
  socc::map::SemanticOccupancyMap map(config);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (map.validate(pose, cloud).empty()) map.integrate(pose, cloud);
  return 0;
}
