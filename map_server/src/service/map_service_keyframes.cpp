// GET_KEYFRAMES: a robot's keyframes as the consistency service holds them now, with their
// optimized poses in the map frame (docs/consistency.md, "The revised trajectory").
#include <algorithm>

#include "map_service.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/pose_history.hpp"

namespace socc::service {

Eigen::Isometry3d MapService::graphToMap() const {
  // A service that saw its grid built rebuilds it at the graph's poses: the graph's frame is the
  // map's. One started on a grid it did not see built (LOAD, a restart its store did not cover)
  // never rebuilds, and its graph is anchored in the first robot's first frame (frame^-1 x
  // pose, robot_corrections.hpp), which that robot's frame maps into the map.
  if (!consistency_foreign_) return Eigen::Isometry3d::Identity();
  return corrections_.frame(consistency_->anchorRobot());
}

keyframes_reply_t MapService::getKeyframes(const keyframes_request_t& request) const {
  keyframes_reply_t reply{};
  reply.keyframes.robot_id = request.robot_id.substr(0, 64);
  if (!consistency_)
    return setStatus(
        reply, Status::failedPrecondition("the map server runs without the consistency service "
                                          "(map_server --consistency): no keyframes"));
  if (request.max_keyframes <= 0)
    return setStatus(reply, Status::invalid("max_keyframes must be > 0"));
  // 10000 keyframes (~0.6 MB) per reply: 30 km at a keyframe per 3 m.
  constexpr std::size_t kMaxKeyframesPerReply = 10000;
  const std::size_t max =
      std::min(static_cast<std::size_t>(request.max_keyframes), kMaxKeyframesPerReply);
  reply.optimizations = consistency_->stats().optimizations;
  reply.pending = consistency_->unprocessed();
  bool truncated = false;
  const auto keyframes =
      consistency_->robotKeyframes(request.robot_id, request.from_seq, max, &truncated);
  if (keyframes.empty())
    return setStatus(reply, Status::notFound("no keyframe of robot '" + reply.keyframes.robot_id +
                                             "' with seq >= " + std::to_string(request.from_seq) +
                                             " in the consistency service"));
  const Eigen::Isometry3d to_map = graphToMap();
  for (const auto& k : keyframes)
    appendPose(reply.keyframes, k.seq, k.utime, toLcm(to_map * k.optimized));
  reply.truncated = truncated;
  return reply;
}

}  // namespace socc::service
