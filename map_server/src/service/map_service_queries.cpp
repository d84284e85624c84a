// Read-only handlers: GET_CHUNK and RENDER.
#include <algorithm>
#include <cmath>

#include "chunk_reply.hpp"
#include "map_service.hpp"
#include "request_checks.hpp"

namespace socc::service {

chunk_reply_t MapService::getChunk(const chunk_request_t& request) const {
  chunk_reply_t reply{};
  setMapInfo(map_, reply);
  if (Status s = checkChunkRequest(request, config_.limits); !s.ok()) {
    setStatus(reply, s);
    return reply;
  }
  map::ChunkQuery query;
  if (request.shape == chunk_request_t::SHAPE_BOX) {
    query.shape = map::ChunkQuery::Shape::kBox;
    query.box_min = Eigen::Vector3d(request.box_min[0], request.box_min[1], request.box_min[2]);
    query.box_max = Eigen::Vector3d(request.box_max[0], request.box_max[1], request.box_max[2]);
  } else {
    query.shape = map::ChunkQuery::Shape::kSphere;
    query.center = Eigen::Vector3d(request.center[0], request.center[1], request.center[2]);
    query.radius = request.radius;
    if (request.since_epoch != 0)
      query.held =
          map::ChunkQuery::Held{request.since_epoch, request.since_version,
                                Eigen::Vector3d(request.since_center[0], request.since_center[1],
                                                request.since_center[2]),
                                request.since_radius};
  }
  query.occupancy_threshold = request.occupancy_threshold;
  query.fields = request.fields;
  // The server maximum caps every reply; a client limit can only lower it.
  const std::int64_t server_max = config_.limits.max_chunk_voxels;
  query.limit = static_cast<std::int32_t>(
      request.limit == 0 ? server_max : std::min<std::int64_t>(request.limit, server_max));

  toChunkReply(map_.queryChunk(query), map_.config().voxel_size, reply);
  if (reply.getEncodedSize() > config_.limits.max_reply_bytes) {
    const std::int64_t bytes = reply.getEncodedSize();
    reply = chunk_reply_t{};
    setMapInfo(map_, reply);
    setStatus(reply, Status::exhausted("reply would be " + std::to_string(bytes) +
                                       " bytes (server limit " +
                                       std::to_string(config_.limits.max_reply_bytes) +
                                       "): ask for a smaller region, fewer fields or a limit"));
  }
  return reply;
}

render_reply_t MapService::render(const render_request_t& request) const {
  render_reply_t reply{};
  if (Status s = checkRenderRequest(request, map_.config().voxel_size, config_.limits); !s.ok()) {
    setStatus(reply, s);
    return reply;
  }
  const double pixel = request.pixel_size > 0.0 ? request.pixel_size : map_.config().voxel_size;
  try {
    const auto image =
        map_.render(Eigen::Vector3d(request.box_min[0], request.box_min[1], request.box_min[2]),
                    Eigen::Vector3d(request.box_max[0], request.box_max[1], request.box_max[2]),
                    pixel, request.mode, request.occupancy_threshold);
    const std::vector<std::uint8_t> png = encodePng(image);
    reply.width = image.width;
    reply.height = image.height;
    reply.png = png;
    reply.num_bytes = static_cast<std::int32_t>(png.size());
  } catch (const std::exception& e) {
    setStatus(reply, Status::internal(std::string("render failed: ") + e.what()));
  }
  return reply;
}

}  // namespace socc::service
