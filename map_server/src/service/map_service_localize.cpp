// LOCALIZE: global localization of a scan in the map (docs/relocalization.md).
#include <chrono>
#include <exception>
#include <string>
#include <variant>

#include "map_service.hpp"
#include "request_checks.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/rpc/status_names.hpp"

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

localize_reply_t failed(localize_reply_t reply, const std::exception& e) {
  setStatus(reply, Status::internal(std::string("localization failed: ") + e.what()));
  return reply;
}

// Seconds from the request's start (its wait for the search thread included).
localize_reply_t finished(localize_reply_t reply, std::chrono::steady_clock::time_point start) {
  reply.seconds = std::chrono::duration<float>(std::chrono::steady_clock::now() - start).count();
  return reply;
}

}  // namespace

localize_reply_t MapService::localize(const localize_request_t& request) {
  std::variant<localize_reply_t, PendingLocalize> begun = beginLocalize(request);
  if (auto* pending = std::get_if<PendingLocalize>(&begun)) {
    pending->run();
    return finishLocalize(std::move(*pending));
  }
  return std::get<localize_reply_t>(std::move(begun));
}

std::variant<localize_reply_t, MapService::PendingLocalize> MapService::beginLocalize(
    const localize_request_t& request, bool may_search) {
  localize_reply_t reply{};
  reply.map_version = map_.version();
  reply.map_epoch = map_.epoch();
  if (Status s = checkLocalizeRequest(request, map_.config(), config_.limits); !s.ok())
    return setStatus(reply, s);
  const auto start = std::chrono::steady_clock::now();
  try {
    std::vector<Eigen::Vector3f> points = pointsOf(request);
    if (request.num_check > 0) {
      addChecks(map_, request, points, reply);
      return finished(std::move(reply), start);
    }
    if (!may_search)
      return setStatus(reply,
                       Status::exhausted("every relocalization search of the server is taken (one "
                                         "running, limits.max_waiting_searches = " +
                                         std::to_string(config_.limits.max_waiting_searches) +
                                         " waiting): " + std::string(rpc::kSearchesBusy)));
    PendingLocalize pending;
    pending.search =
        localizer_.prepare(map_, std::move(points), hintOf(request), request.max_candidates);
    pending.reply = std::move(reply);
    pending.start = start;
    return pending;
  } catch (const std::exception& e) {
    return failed(std::move(reply), e);
  }
}

void MapService::PendingLocalize::run(const std::atomic<bool>* cancel) {
  try {
    search.run(cancel);
  } catch (...) {
    error = std::current_exception();
  }
}

localize_reply_t MapService::finishLocalize(PendingLocalize pending) const {
  // A grid swapped in while the search ran (a map correction, LOAD, CLEAR): its hypotheses are
  // in the old grid's frame and cannot be ranked on the new one. The client asks again
  // (MapClient's resend rule for kSearchesBusy) and is searched in the new grid.
  if (map_.epoch() != pending.reply.map_epoch)
    return setStatus(pending.reply,
                     Status::exhausted("the map was replaced while the search ran: " +
                                       std::string(rpc::kSearchesBusy)));
  try {
    if (pending.error) std::rethrow_exception(pending.error);
    addCandidates(localization::GlobalLocalizer::finish(map_, std::move(pending.search)),
                  pending.reply);
  } catch (const std::exception& e) {
    return failed(std::move(pending.reply), e);
  }
  return finished(std::move(pending.reply), pending.start);
}

}  // namespace socc::service
