#include "socc/odom/chunk_frame_gate.hpp"

namespace socc::odom {

bool ChunkFrameGate::admit(std::int64_t epoch, std::int64_t version,
                           std::int64_t integrate_version) {
  // Every change of the map (another robot's Integrate, a swap) raises its version.
  if (epoch_ && epoch != *epoch_ && version != integrate_version) return false;
  epoch_ = epoch;
  return true;
}

}  // namespace socc::odom
