#include "socc/odom/service_map_access.hpp"

#include <sstream>
#include <stdexcept>

#include "socc/pose_conversion.hpp"
#include "socc/reply_header_t.hpp"
#include "socc/rpc/resend_rule.hpp"

namespace socc::odom {

std::string callError(const char* what, const rpc::CallError& e, int attempts) {
  std::ostringstream out;
  out << what << " failed after " << attempts << " attempt(s): "
      << (e.timed_out ? "no reply from the map server (is map_server running on this LCM URL?)"
                      : e.message + " (" + rpc::statusName(e.status) + ")");
  return out.str();
}

bool costsOnlyTheSearch(const rpc::CallError& e, NoReply no_reply) {
  if (e.timed_out) return no_reply == NoReply::kBusy;
  return rpc::matchingRule(e.status, e.message, {rpc::searchesBusyRule({})}) == 0;
}

namespace {

// A failed search call: MapBusy when the search may simply be asked again later
// (costsOnlyTheSearch), any other failure as it is.
[[noreturn]] void searchFailed(const char* what, const rpc::CallError& e, int attempts,
                               NoReply no_reply) {
  const std::string text = callError(what, e, attempts);
  if (costsOnlyTheSearch(e, no_reply)) throw MapBusy(text);
  throw std::runtime_error(text);
}

}  // namespace

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
  if (!reply.ok()) searchFailed("LOCALIZE", reply.error, reply.attempts, no_reply_);
  std::vector<Eigen::Isometry3d> out;
  for (const pose3d_t& pose : reply.reply->pose) {
    if (!checkPose(pose, 1e7).empty()) continue;  // a malformed candidate is no candidate
    out.push_back(fromLcm(pose));
  }
  return out;
}

std::vector<SpaceCheck> ServiceMapAccess::check(const std::vector<Eigen::Vector3f>& scan,
                                                const std::vector<Eigen::Isometry3d>& poses) {
  localize_request_t request = rpc::makeLocalizeRequest(scan, 1);
  for (const Eigen::Isometry3d& pose : poses) request.check_pose.push_back(toLcm(pose));
  request.num_check = static_cast<std::int32_t>(request.check_pose.size());
  const rpc::Result<localize_reply_t> reply = client_.localize(std::move(request));
  if (!reply.ok()) searchFailed("LOCALIZE", reply.error, reply.attempts, no_reply_);
  std::vector<SpaceCheck> out;
  for (std::int32_t i = 0; i < reply.reply->num_checked; ++i)
    out.push_back({reply.reply->observed[static_cast<std::size_t>(i)],
                   reply.reply->free[static_cast<std::size_t>(i)]});
  return out;
}

LocalMap ServiceMapAccess::chunk(const Eigen::Vector3d& center) {
  chunk_request_t request = rpc::sphereChunkRequest(center, config_.chunk_radius);
  request.occupancy_threshold = static_cast<float>(config_.occupancy_threshold);
  const rpc::Result<chunk_reply_t> reply = client_.getChunk(request);
  if (!reply.ok()) searchFailed("GET_CHUNK", reply.error, reply.attempts, no_reply_);
  return LocalMap::fromChunk(*reply.reply, config_.occupancy_threshold);
}

}  // namespace socc::odom
