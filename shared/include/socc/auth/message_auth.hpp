#pragma once
// Shared-key authentication of LCM requests (see docs/security.md).
// Any generated request type Msg whose `header` is a socc::request_header_t can be signed:
// the MAC is HMAC-SHA256 over the LCM encoding of the whole message (type hash included, so
// a MAC is bound to its request type) with auth_counter set and mac empty (mac_len = 0).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "socc/auth/auth_counter.hpp"
#include "socc/auth/hmac.hpp"
#include "socc/auth/replay_guard.hpp"
#include "socc/auth/shared_key.hpp"
#include "socc/request_header_t.hpp"

namespace socc::auth {

namespace detail {
/// HMAC of msg's encoding; msg must already have mac_len = 0 and an empty mac.
template <class Msg>
Mac macOfUnsigned(const Msg& msg, const SharedKey& key) {
  const int size = msg.getEncodedSize();
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(size > 0 ? size : 0));
  if (size <= 0 || msg.encode(buf.data(), 0, size) != size)
    throw std::invalid_argument("sign: message does not encode (array lengths inconsistent?)");
  return hmacSha256(key, buf.data(), buf.size());
}
}  // namespace detail

/// Sets header.auth_counter = counter and header.mac = HMAC(key, encoding with empty mac).
/// Every change to msg after signing invalidates the MAC; a retry must be re-signed with a
/// new counter (the server rejects a reused counter as a replay).
template <class Msg>
void sign(Msg& msg, const SharedKey& key, std::int64_t counter) {
  msg.header.auth_counter = counter;
  msg.header.mac_len = 0;
  msg.header.mac.clear();
  const Mac mac = detail::macOfUnsigned(msg, key);
  msg.header.mac.assign(mac.begin(), mac.end());
  msg.header.mac_len = static_cast<std::int32_t>(mac.size());
}

/// Why a request was rejected. The MAC cannot tell a forged MAC from a tampered payload or a
/// wrong key: all three are kBadMac.
enum class AuthFailure {
  kNone,
  kMissingMac,
  kMalformedMac,
  kBadCounter,
  kBadMac,
  kReplayed,
  kStale
};

struct AuthResult {
  bool ok = false;
  AuthFailure failure = AuthFailure::kNone;
  std::string reason;  // human-readable, empty when ok; safe to send back to the client
};

/// Server side: checks MAC and counter and remembers accepted counters per client_id.
/// Not thread-safe (the service serialises requests).
class Verifier {
 public:
  explicit Verifier(SharedKey key) : key_(std::move(key)) {}

  /// Accepts msg when its MAC is valid and header.auth_counter > the last counter accepted
  /// from header.client_id; only then is the counter recorded. msg must have array lengths
  /// that match its vectors (as decode() produces), since it is re-encoded.
  template <class Msg>
  AuthResult verify(const Msg& msg) {
    // Before encoding: encode() trusts mac_len, a lying one would read past the vector.
    if (AuthResult r = checkHeader(msg.header); !r.ok) return r;
    const int size = msg.getEncodedSize();
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(size > 0 ? size : 0));
    if (size <= 0 || msg.encode(buf.data(), 0, size) != size)
      return fail(AuthFailure::kMalformedMac, "request does not encode");
    return verifyEncoded(msg.header, buf.data(), buf.size());
  }

  /// The same check on a request exactly as received (any request type: the header must be
  /// its first field, as in all socc requests); header is its decoded header. Avoids
  /// re-encoding large requests: the MAC is computed over the bytes with the mac cut out.
  AuthResult verifyEncoded(const request_header_t& header, const std::uint8_t* data,
                           std::size_t size);

  ReplayGuard& replayGuard() { return guard_; }
  const ReplayGuard& replayGuard() const { return guard_; }

 private:
  static AuthResult fail(AuthFailure failure, std::string reason);
  static AuthResult checkHeader(const request_header_t& header);

  SharedKey key_;
  ReplayGuard guard_;
};

std::string toString(AuthFailure failure);

}  // namespace socc::auth
