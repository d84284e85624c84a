// LOCALIZE: global localization of a scan in the map (docs/relocalization.md).
#include <chrono>
#include <exception>

#include "map_service.hpp"
#include "request_checks.hpp"
#include "socc/pose_conversion.hpp"

namespace socc::service {
namespace {

std::vector<Eigen::Vector3f> pointsOf(const localize_request_t& request) {
  std::vector<Eigen::Vector3f> points(static_cast<std::size_t>(request.num_points));
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = {request.xyz[0][i], request.xyz[1][i], request.xyz[2][i]};
  return points;
}

std::optional<localization::LocalizeHint> hintOf(const localize_request_t& request) {
  if (request.hint_radius <= 0.0) return std::nullopt;
  localization::LocalizeHint hint;
  hint.position = {request.hint_position[0], request.hint_position[1], request.hint_position[2]};
  hint.yaw = request.hint_yaw;
  hint.radius = request.hint_radius;
  hint.yaw_tolerance = request.hint_yaw_tolerance;
  return hint;
}

void addCandidates(const localization::LocalizeAnswer& answer, localize_reply_t& reply) {
  reply.map_keypoints = static_cast<std::int32_t>(answer.map_keypoints);
  reply.scan_keypoints = static_cast<std::int32_t>(answer.scan_keypoints);
  for (const localization::PoseCandidate& c : answer.candidates) {
    reply.pose.push_back(toLcm(c.pose));
    reply.inliers.push_back(c.inliers);
    reply.inlier_fraction.push_back(static_cast<float>(c.inlier_fraction));
  }
  reply.num_candidates = static_cast<std::int32_t>(reply.pose.size());
}

// Check mode: where the points land in the map at each given pose.
void addChecks(const map::SemanticOccupancyMap& map, const localize_request_t& request,
               const std::vector<Eigen::Vector3f>& points, localize_reply_t& reply) {
  for (const pose3d_t& pose : request.check_pose) {
    const localization::SpaceCheck check = localization::checkFreeSpace(map, points, fromLcm(pose));
    reply.observed.push_back(static_cast<float>(check.observed));
    reply.free.push_back(static_cast<float>(check.free));
  }
  reply.num_checked = static_cast<std::int32_t>(reply.observed.size());
}

}  // namespace

localize_reply_t MapService::localize(const localize_request_t& request) {
  localize_reply_t reply{};
  reply.map_version = map_.version();
  if (Status s = checkLocalizeRequest(request, map_.config(), config_.limits); !s.ok())
    return setStatus(reply, s);
  const auto start = std::chrono::steady_clock::now();
  try {
    const std::vector<Eigen::Vector3f> points = pointsOf(request);
    if (request.num_check > 0)
      addChecks(map_, request, points, reply);
    else
      addCandidates(localizer_.localize(map_, points, hintOf(request), request.max_candidates),
                    reply);
  } catch (const std::exception& e) {
    setStatus(reply, Status::internal(std::string("localization failed: ") + e.what()));
  }
  reply.seconds = std::chrono::duration<float>(std::chrono::steady_clock::now() - start).count();
  return reply;
}

}  // namespace socc::service
