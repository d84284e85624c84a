#pragma once
// The request harnesses' view of the map server: its decode path and a MapService with small
// limits (so one input stays fast) and a little map content.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "service/map_service.hpp"
#include "service/wire_guard.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/rpc/safe_decode.hpp"
#include "socc/wire_arrays.hpp"

namespace socc::fuzz {

/// What the map server does with received bytes before any handler runs (RequestRouter):
/// the wire guard refuses impossible counts, then the checked decode.
template <class Request>
std::optional<Request> decodeRequest(const std::uint8_t* data, std::size_t size,
                                     bool integrate = false) {
  if (size > 64u << 20) return std::nullopt;
  const int n = static_cast<int>(size);
  const std::string why =
      integrate ? service::checkIntegrateWire(data, n) : service::checkRequestHeaderWire(data, n);
  if (!why.empty()) return std::nullopt;
  return rpc::safeDecode<Request>(data, n);
}

inline service::ServerConfig smallServerConfig() {
  service::ServerConfig config;
  config.map.voxel_size = 1.0;
  config.map.max_range = 30.0;
  config.limits.max_chunk_voxels = 20'000;
  config.limits.max_region_extent = 200.0;
  config.limits.max_reply_bytes = 4'000'000;
  config.limits.max_render_pixels = 40'000;
  config.limits.max_robots = 8;
  config.limits.max_localize_points = 2'000;
  config.localization.search.max_iterations = 200;  // the search's cost is not what is fuzzed
  const char* tmp = std::getenv("TMPDIR");
  config.file_dir = tmp ? tmp : "/tmp";
  return config;
}

/// A small ring of labelled points around the origin, robot "seed" at seq, 0.1 s per seq.
inline integrate_request_t seedScan(std::int64_t seq) {
  integrate_request_t r{};
  r.header.client_id = "seed";
  r.seq = seq;
  r.scan_utime = seq * 100'000;
  r.sensor_pose.quaternion[0] = 1.0;
  Points points;
  for (int i = 0; i < 64; ++i) {
    const float a = static_cast<float>(i) * 0.098f;
    points.emplace_back(8.f * std::cos(a), 8.f * std::sin(a), static_cast<float>(i % 3) - 1.f);
    r.label.push_back(static_cast<std::uint8_t>(i % 20));
  }
  r.xyz_resolution = wire::quantizePoints(points, r.xyz);
  r.num_points = static_cast<std::int32_t>(r.label.size());
  r.num_labels = r.num_points;
  return r;
}

/// A service whose map holds seedScan(1).
inline service::MapService populatedService() {
  service::MapService svc(smallServerConfig());
  svc.integrate(seedScan(1));
  return svc;
}

}  // namespace socc::fuzz
