#pragma once
// Client side of the map service (gRPC-style request/response over LCM).
// Each call publishes a request on SOCC/<SERVICE>/REQ and waits for the reply with the same
// request_id on SOCC/<SERVICE>/REP/<client_id>; on timeout it retries the SAME request
// (same request_id, and for Integrate the same seq, so the server applies it once). With a
// key file every attempt is signed with a new auth counter (docs/security.md).
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "socc/chunk_reply_t.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/gravity_reference.hpp"
#include "socc/integrate_reply_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/keyframes_reply_t.hpp"
#include "socc/localize_reply_t.hpp"
#include "socc/localize_request_t.hpp"
#include "socc/map_command_reply_t.hpp"
#include "socc/map_command_request_t.hpp"
#include "socc/point_cloud.hpp"
#include "socc/render_reply_t.hpp"
#include "socc/render_request_t.hpp"
#include "socc/robot_pose_reply_t.hpp"
#include "socc/robot_status_reply_t.hpp"
#include "socc/robot_status_request_t.hpp"
#include "socc/rpc/status_names.hpp"
#include "socc/stats_reply_t.hpp"

namespace socc::rpc {

struct ClientOptions {
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  std::string client_id = "robot1";
  std::chrono::milliseconds timeout{2000};  // per attempt
  int max_attempts = 5;
  // Optional shared key (mode 0600): every request is signed (HMAC-SHA256, docs/security.md).
  std::string key_file;
};

/// Error of a call: transport (no reply after all attempts) or a non-OK status.
struct CallError {
  std::int8_t status = 0;  // reply_header_t code; INTERNAL for timeouts
  std::string message;
  bool timed_out = false;
};

/// The result of a call: the reply when it arrived with status OK, else the error.
template <typename Reply>
struct Result {
  std::optional<Reply> reply;
  CallError error;
  int attempts = 0;
  std::int64_t bytes_received = 0;  // encoded reply size
  bool ok() const { return reply.has_value(); }
};

class MapClient {
 public:
  /// Throws std::runtime_error on a bad URL or client id, or an unusable key file.
  explicit MapClient(ClientOptions options);
  ~MapClient();
  MapClient(const MapClient&) = delete;
  MapClient& operator=(const MapClient&) = delete;

  const ClientOptions& options() const;
  /// Whether the server ever replied to this client (any status): a server that answered
  /// before and is silent now is busy or gone, one that never answered may not be running.
  bool answered() const;

  /// The header fields (request id, client id, reply channel, time, auth) are filled in here.
  Result<integrate_reply_t> integrate(integrate_request_t request);
  Result<chunk_reply_t> getChunk(chunk_request_t request);
  Result<stats_reply_t> getStats();
  /// max_history > 0 also asks for up to that many history poses with seq >= history_from_seq
  /// (the server sends at most 10000 per reply and sets history_truncated when more follow).
  Result<robot_pose_reply_t> getRobotPose(const std::string& robot_id, std::int32_t max_history = 0,
                                          std::int64_t history_from_seq = 0);
  /// GET_KEYFRAMES: robot_id's keyframes with seq >= from_seq and their optimized map-frame
  /// poses (map_server --consistency, docs/consistency.md); at most max_keyframes (the server
  /// sends at most 10000 per reply and sets truncated when more follow). FAILED_PRECONDITION
  /// from a server without the consistency service, NOT_FOUND when it holds no such keyframe.
  Result<keyframes_reply_t> getKeyframes(const std::string& robot_id, std::int64_t from_seq = 0,
                                         std::int32_t max_keyframes = 10000);
  Result<map_command_reply_t> command(map_command_request_t request);
  Result<render_reply_t> render(render_request_t request);
  /// LOCALIZE: ranked candidate poses of a scan in the map (docs/relocalization.md); waits up to
  /// 30 s per attempt (a search over a large map takes seconds).
  Result<localize_reply_t> localize(localize_request_t request);
  /// ROBOT_STATUS: reports this client's (= robot's) tracking state (robot_status_request_t
  /// constants) at frame seq / scan time utime. LOST and RELOCALIZING make the server refuse
  /// its INTEGRATEs (FAILED_PRECONDITION) until it reports TRACKING or DEGRADED again.
  /// NOT_FOUND before the robot's first accepted INTEGRATE.
  Result<robot_status_reply_t> reportTracking(std::int8_t tracking_state, const std::string& reason,
                                              std::int64_t seq, std::int64_t utime);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Convenience builders with the documented defaults (occupancy threshold 0.5, features).
chunk_request_t sphereChunkRequest(const Eigen::Vector3d& center, double radius,
                                   std::int32_t fields = chunk_request_t::FIELD_FEATURES);
/// A LOCALIZE request for points (sensor frame) without a hint.
localize_request_t makeLocalizeRequest(const std::vector<Eigen::Vector3f>& points,
                                       std::int32_t max_candidates);
/// An INTEGRATE request of cloud (sensor frame, quantized: wire::quantizePoints), with the
/// scan's gravity reference when it has one (else gravity_sigma 0). Throws
/// std::invalid_argument for a non-finite point.
integrate_request_t makeIntegrateRequest(
    std::int64_t seq, std::int64_t scan_utime, const Eigen::Isometry3d& sensor_pose,
    const LabeledCloud& cloud, const std::optional<GravityReference>& gravity = std::nullopt);

}  // namespace socc::rpc
