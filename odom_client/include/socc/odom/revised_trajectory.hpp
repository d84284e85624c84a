#pragma once
// The robot's trajectory as the server's pose graph revised it (docs/consistency.md, "The
// revised trajectory"): at the end of a run odom_client asks the consistency service for its
// keyframes (GET_KEYFRAMES) and writes its output poses moved by their revisions
// (socc/trajectory_revision.hpp) beside poses_kitti.txt / poses_tum.txt.
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "socc/kitti_io.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/trajectory_revision.hpp"

namespace socc::odom {

/// The robot's keyframes with seq >= from_seq (all pages), or why there are none.
struct KeyframeFetch {
  std::vector<KeyframeEstimate> keyframes;
  int optimizations = 0;
  int pending = 0;    // the service's keyframes not yet in its graph when the last page came
  std::string error;  // empty: keyframes holds them
};
KeyframeFetch fetchKeyframes(rpc::MapClient& client, const std::string& robot_id,
                             std::int64_t from_seq);

/// Fetches the keyframes (waiting up to wait while the service still has keyframes to
/// process), revises trajectory and writes poses_revised_kitti.txt / poses_revised_tum.txt into
/// out_dir. Returns the line for stderr: what was written, or why nothing was (a server without
/// the consistency service, no keyframe of this robot, a file that cannot be written): never
/// throws.
std::string writeRevisedTrajectory(rpc::MapClient& client, const std::string& robot_id,
                                   const Trajectory& trajectory,
                                   const std::vector<FrameCorrection>& corrections,
                                   const std::filesystem::path& out_dir,
                                   std::chrono::milliseconds wait);

}  // namespace socc::odom
