#include "socc/odom/service_map_access.hpp"

#include <sstream>
#include <stdexcept>

#include "socc/pose_conversion.hpp"

namespace socc::odom {

std::string callError(const char* what, const rpc::CallError& e, int attempts) {
  std::ostringstream out;
  out << what << " failed after " << attempts << " attempt(s): "
      << (e.timed_out ? "no reply from the map server (is map_server running on this LCM URL?)"
                      : e.message + " (" + rpc::statusName(e.status) + ")");
  return out.str();
}

std::vector<Eigen::Isometry3d> ServiceMapAccess::candidates(
    const std::vector<Eigen::Vector3f>& scan, const std::optional<PoseHint>& hint, int max) {
  localize_request_t request = rpc::makeLocalizeRequest(scan, max);
  if (hint) {
    for (int i = 0; i < 3; ++i) request.hint_position[i] = hint->position[i];
    request.hint_yaw = hint->yaw;
    request.hint_radius = hint->radius;
    request.hint_yaw_tolerance = hint->yaw_tolerance;
  }
  const rpc::Result<localize_reply_t> reply = client_.localize(std::move(request));
  if (!reply.ok()) throw std::runtime_error(callError("LOCALIZE", reply.error, reply.attempts));
  std::vector<Eigen::Isometry3d> out;
  for (const pose3d_t& pose : reply.reply->pose) {
    if (!checkPose(pose, 1e7).empty()) continue;  // a malformed candidate is no candidate
    out.push_back(fromLcm(pose));
  }
  return out;
}

LocalMap ServiceMapAccess::chunk(const Eigen::Vector3d& center) {
  chunk_request_t request = rpc::sphereChunkRequest(center, config_.chunk_radius);
  request.occupancy_threshold = static_cast<float>(config_.occupancy_threshold);
  const rpc::Result<chunk_reply_t> reply = client_.getChunk(request);
  if (!reply.ok()) throw std::runtime_error(callError("GET_CHUNK", reply.error, reply.attempts));
  return LocalMap::fromChunk(*reply.reply, config_.occupancy_threshold);
}

}  // namespace socc::odom
