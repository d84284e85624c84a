#include "socc/odom/revised_trajectory.hpp"

#include <sstream>
#include <thread>

#include "socc/pose_conversion.hpp"
#include "socc/pose_history.hpp"

namespace socc::odom {
KeyframeFetch fetchKeyframes(rpc::MapClient& client, const std::string& robot_id,
                             std::int64_t from_seq) {
  KeyframeFetch out;
  for (;;) {
    const rpc::Result<keyframes_reply_t> page = client.getKeyframes(robot_id, from_seq);
    if (!page.ok()) {
      out.keyframes.clear();
      out.error = "GET_KEYFRAMES: " + std::string(rpc::statusName(page.error.status)) + ": " +
                  page.error.message;
      return out;
    }
    const pose_history_t& h = page.reply->keyframes;
    if (h.seq.size() != static_cast<std::size_t>(h.num_poses) || h.translation.size() != 3 ||
        h.quaternion.size() != 4) {
      out.error = "GET_KEYFRAMES: malformed reply";
      return out;
    }
    for (std::size_t i = 0; i < h.seq.size(); ++i)
      out.keyframes.push_back({h.seq[i], fromLcm(poseAt(h, i))});
    out.optimizations = page.reply->optimizations;
    out.pending = page.reply->pending;
    if (!page.reply->truncated || h.seq.empty()) return out;
    from_seq = h.seq.back() + 1;
  }
}

std::string writeRevisedTrajectory(rpc::MapClient& client, const std::string& robot_id,
                                   const Trajectory& trajectory,
                                   const std::vector<FrameCorrection>& corrections,
                                   const std::filesystem::path& out_dir,
                                   std::chrono::milliseconds wait) {
  if (trajectory.seqs.empty()) return "no revised trajectory: no frame was output";
  const auto until = std::chrono::steady_clock::now() + wait;
  KeyframeFetch fetch = fetchKeyframes(client, robot_id, trajectory.seqs.front());
  // The service's worker may still be placing the last keyframes into its graph.
  while (fetch.error.empty() && fetch.pending > 0 && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    fetch = fetchKeyframes(client, robot_id, trajectory.seqs.front());
  }
  if (!fetch.error.empty())
    return "no revised trajectory (poses_revised_*.txt not written): " + fetch.error;
  RevisedTrajectory revised;
  try {
    revised = reviseTrajectory(trajectory.seqs, trajectory.poses, fetch.keyframes, corrections);
    if (revised.keyframes == 0)
      return "no revised trajectory (poses_revised_*.txt not written): none of the " +
             std::to_string(fetch.keyframes.size()) + " keyframes is a frame of this run";
    writeKittiPoses(out_dir / "poses_revised_kitti.txt", revised.poses);
    writeTumPoses(out_dir / "poses_revised_tum.txt", revised.poses, trajectory.stamps);
  } catch (const std::exception& e) {  // the run's own outputs stand: no failure for this
    return std::string("no revised trajectory: ") + e.what();
  }
  std::ostringstream line;
  line.precision(3);
  line << std::fixed << "trajectory revised by the server's pose graph (" << revised.keyframes
       << " keyframes, " << fetch.optimizations << " optimizations; poses moved up to "
       << revised.max_shift << " m) -> poses_revised_kitti.txt, poses_revised_tum.txt";
  if (fetch.pending > 0)
    line << "; the service still had " << fetch.pending
         << " keyframes to process (frames after the last returned keyframe keep its revision)";
  return line.str();
}

}  // namespace socc::odom
