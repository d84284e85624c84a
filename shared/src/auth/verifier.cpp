#include <cstring>

#include "socc/auth/message_auth.hpp"

namespace socc::auth {

namespace {
constexpr std::size_t kHashBytes = 8;    // LCM type fingerprint before the first field
constexpr std::size_t kLengthBytes = 4;  // the int32 mac_len before the mac bytes
}  // namespace

AuthResult Verifier::fail(AuthFailure failure, std::string reason) {
  return AuthResult{false, failure, std::move(reason)};
}

AuthResult Verifier::checkHeader(const request_header_t& header) {
  if (header.mac_len == 0 && header.mac.empty())
    return fail(AuthFailure::kMissingMac, "request is not signed");
  if (header.mac_len != static_cast<std::int32_t>(kMacBytes) || header.mac.size() != kMacBytes)
    return fail(AuthFailure::kMalformedMac,
                "mac must have " + std::to_string(kMacBytes) + " bytes (HMAC-SHA256)");
  if (header.auth_counter <= 0)
    return fail(AuthFailure::kBadCounter, "auth_counter must be positive");
  return AuthResult{true, AuthFailure::kNone, {}};
}

AuthResult Verifier::verifyEncoded(const request_header_t& header, const std::uint8_t* data,
                                   std::size_t size) {
  if (AuthResult r = checkHeader(header); !r.ok) return r;
  // Layout: [type hash][header ... mac_len mac][rest of the request]. The signed bytes are
  // the same with mac_len = 0 and the mac removed.
  const std::size_t header_end =
      kHashBytes + static_cast<std::size_t>(header._getEncodedSizeNoHash());
  const std::uint8_t expected_len[kLengthBytes] = {0, 0, 0, static_cast<std::uint8_t>(kMacBytes)};
  if (data == nullptr || size < header_end ||
      std::memcmp(data + header_end - kMacBytes - kLengthBytes, expected_len, kLengthBytes) != 0 ||
      std::memcmp(data + header_end - kMacBytes, header.mac.data(), kMacBytes) != 0)
    return fail(AuthFailure::kMalformedMac, "request bytes do not match its header");
  const std::uint8_t zero_len[kLengthBytes] = {0, 0, 0, 0};
  const Mac expected = hmacSha256(
      key_, {ByteRange{data, header_end - kMacBytes - kLengthBytes},
             ByteRange{zero_len, kLengthBytes}, ByteRange{data + header_end, size - header_end}});

  // MAC before counter: an unauthenticated sender learns nothing about the counter state.
  if (!macEqual(expected, header.mac.data()))
    return fail(AuthFailure::kBadMac, "mac does not match (wrong key or modified request)");
  switch (guard_.check(header.client_id, header.auth_counter)) {
    case CounterCheck::kReplayed:
      return fail(AuthFailure::kReplayed,
                  "auth_counter already used by '" + header.client_id + "' (replay)");
    case CounterCheck::kStale:
      return fail(AuthFailure::kStale,
                  "auth_counter lower than the last accepted one of '" + header.client_id + "'");
    case CounterCheck::kFresh:
      break;
  }
  guard_.accept(header.client_id, header.auth_counter);
  return AuthResult{true, AuthFailure::kNone, {}};
}

std::string toString(AuthFailure failure) {
  switch (failure) {
    case AuthFailure::kNone:
      return "ok";
    case AuthFailure::kMissingMac:
      return "missing mac";
    case AuthFailure::kMalformedMac:
      return "malformed mac";
    case AuthFailure::kBadCounter:
      return "bad counter";
    case AuthFailure::kBadMac:
      return "bad mac";
    case AuthFailure::kReplayed:
      return "replayed";
    case AuthFailure::kStale:
      return "stale counter";
  }
  return "unknown";
}

}  // namespace socc::auth
