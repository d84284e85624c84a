#pragma once
// HMAC-SHA256 (OpenSSL) and a constant-time comparison of MACs.
#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "socc/auth/shared_key.hpp"

namespace socc::auth {

inline constexpr std::size_t kMacBytes = 32;
using Mac = std::array<std::uint8_t, kMacBytes>;

struct ByteRange {
  const std::uint8_t* data;
  std::size_t size;
};

/// HMAC of the concatenation of the pieces (no copy into one buffer).
Mac hmacSha256(const SharedKey& key, std::initializer_list<ByteRange> pieces);
inline Mac hmacSha256(const SharedKey& key, const std::uint8_t* data, std::size_t size) {
  return hmacSha256(key, {ByteRange{data, size}});
}
/// Constant-time (CRYPTO_memcmp) so the comparison leaks nothing about where MACs differ.
bool macEqual(const Mac& a, const std::uint8_t* b);

}  // namespace socc::auth
