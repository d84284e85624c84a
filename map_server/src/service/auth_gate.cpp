#include "auth_gate.hpp"

#include <utility>

namespace socc::service {

AuthGate::AuthGate(auth::SharedKey key, bool auth_queries)
    : verifier_(std::move(key)), auth_queries_(auth_queries) {}

std::string AuthGate::admit(std::string_view service, bool state_changing,
                            const request_header_t& header, const std::uint8_t* data, int size) {
  if (!state_changing && !auth_queries_) return {};
  if (size < 0) return std::string(service) + " requires authentication: empty request";
  const auth::AuthResult result =
      verifier_.verifyEncoded(header, data, static_cast<std::size_t>(size));
  if (result.ok) return {};
  // The reason names no secret (see toString/AuthResult), so it can go back to the client.
  return std::string(service) + " requires authentication (" + auth::toString(result.failure) +
         "): " + result.reason;
}

}  // namespace socc::service
