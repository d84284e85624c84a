#pragma once
// RequestGate with shared-key authentication (docs/security.md): state-changing requests, and
// optionally read-only queries too, must carry a valid HMAC-SHA256 and a fresh per-client
// counter. The verifier's replay state is exposed so the service can persist it in snapshots.
#include <cstdint>
#include <string>
#include <string_view>

#include "request_gate.hpp"
#include "socc/auth/message_auth.hpp"

namespace socc::service {

class AuthGate final : public RequestGate {
 public:
  /// auth_queries: also require a MAC on GET_CHUNK, GET_STATS, GET_ROBOT_POSE, RENDER,
  /// LOCALIZE and GET_KEYFRAMES (every request that changes nothing).
  AuthGate(auth::SharedKey key, bool auth_queries);

  std::string admit(std::string_view service, bool state_changing, const request_header_t& header,
                    const std::uint8_t* data, int size) override;

  auth::ReplayGuard& replayGuard() { return verifier_.replayGuard(); }

 private:
  auth::Verifier verifier_;
  bool auth_queries_;
};

}  // namespace socc::service
