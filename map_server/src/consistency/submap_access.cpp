#include "submap_access.hpp"

#include <algorithm>

#include "global_localizer.hpp"
#include "service/chunk_reply.hpp"

namespace socc::consistency {

SubmapAccess::SubmapAccess(const map::MapConfig& config, const std::vector<SubmapScan>& scans,
                           std::vector<Eigen::Isometry3d> guesses, double chunk_radius)
    : map_(config), guesses_(std::move(guesses)), chunk_radius_(chunk_radius) {
  for (const SubmapScan& s : scans) {
    LabeledCloud cloud;
    cloud.points = *s.points;
    if (map_.validate(s.pose, cloud).empty()) map_.integrate(s.pose, cloud);
  }
}

std::vector<Eigen::Isometry3d> SubmapAccess::candidates(
    const std::vector<Eigen::Vector3f>& /*scan*/, const std::optional<odom::PoseHint>& /*hint*/,
    int max) {
  std::vector<Eigen::Isometry3d> out = guesses_;
  if (static_cast<int>(out.size()) > max) out.resize(static_cast<std::size_t>(std::max(0, max)));
  return out;
}

odom::LocalMap SubmapAccess::chunk(const Eigen::Vector3d& center) {
  map::ChunkQuery query;
  query.shape = map::ChunkQuery::Shape::kSphere;
  query.center = center;
  query.radius = chunk_radius_;
  query.fields = map::ChunkQuery::kFeatures | map::ChunkQuery::kMoments;
  query.occupancy_threshold = map_.config().occupancy_threshold;
  return odom::LocalMap::fromChunk(service::queryChunkReply(map_, query),
                                   map_.config().occupancy_threshold);
}

std::vector<odom::SpaceCheck> SubmapAccess::check(const std::vector<Eigen::Vector3f>& scan,
                                                  const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<odom::SpaceCheck> out;
  out.reserve(poses.size());
  for (const Eigen::Isometry3d& pose : poses) {
    const localization::SpaceCheck c = localization::checkFreeSpace(map_, scan, pose);
    out.push_back({c.observed, c.free});
  }
  return out;
}

}  // namespace socc::consistency
