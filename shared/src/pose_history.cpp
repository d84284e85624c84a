#include "socc/pose_history.hpp"

namespace socc {

void appendPose(pose_history_t& h, std::int64_t seq, std::int64_t utime, const pose3d_t& pose) {
  h.translation.resize(3);
  h.quaternion.resize(4);
  h.seq.push_back(seq);
  h.scan_utime.push_back(utime);
  for (int c = 0; c < 3; ++c) h.translation[c].push_back(pose.translation[c]);
  for (int c = 0; c < 4; ++c) h.quaternion[c].push_back(pose.quaternion[c]);
  ++h.num_poses;
}

pose3d_t poseAt(const pose_history_t& h, std::size_t i) {
  pose3d_t p{};
  for (std::size_t c = 0; c < 3; ++c) p.translation[c] = h.translation[c][i];
  for (std::size_t c = 0; c < 4; ++c) p.quaternion[c] = h.quaternion[c][i];
  return p;
}

}  // namespace socc
