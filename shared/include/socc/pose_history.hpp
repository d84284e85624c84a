#pragma once
// Entries of socc::pose_history_t (a robot's poses by seq, arrays by component: docs/lcm.md
// "Array layout"): the one way to append an entry and to read one back.
#include <cstddef>
#include <cstdint>

#include "socc/pose3d_t.hpp"
#include "socc/pose_history_t.hpp"

namespace socc {

/// Appends (seq, utime, pose) as h's last entry.
void appendPose(pose_history_t& h, std::int64_t seq, std::int64_t utime, const pose3d_t& pose);
/// Entry i's pose; i < h.num_poses, h decoded (decode yields every row) or built by appendPose.
pose3d_t poseAt(const pose_history_t& h, std::size_t i);

}  // namespace socc
