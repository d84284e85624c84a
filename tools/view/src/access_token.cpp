#include "access_token.hpp"

#include <openssl/crypto.h>

#include <cstdint>
#include <string_view>

#include "socc/auth/hmac.hpp"

namespace socc::view {

std::string accessToken(const auth::SharedKey& key) {
  constexpr std::string_view kPurpose = "socc-view access v1";
  const auth::Mac mac = auth::hmacSha256(
      key, reinterpret_cast<const std::uint8_t*>(kPurpose.data()), kPurpose.size());
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (const std::uint8_t b : mac) {
    hex.push_back(kHex[b >> 4]);
    hex.push_back(kHex[b & 15]);
  }
  return hex;
}

bool tokenMatches(const std::string& expected, const std::string& presented) {
  return expected.size() == presented.size() &&
         CRYPTO_memcmp(expected.data(), presented.data(), expected.size()) == 0;
}

}  // namespace socc::view
