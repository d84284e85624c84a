#include "socc/auth/hmac.hpp"

#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/params.h>

#include <memory>
#include <stdexcept>

namespace socc::auth {

namespace {
struct MacDeleter {
  void operator()(EVP_MAC* m) const { EVP_MAC_free(m); }
};
struct MacCtxDeleter {
  void operator()(EVP_MAC_CTX* c) const { EVP_MAC_CTX_free(c); }
};
[[noreturn]] void fail(const char* step) {
  throw std::runtime_error(std::string("HMAC-SHA256 failed: ") + step);
}
}  // namespace

Mac hmacSha256(const SharedKey& key, std::initializer_list<ByteRange> pieces) {
  const std::unique_ptr<EVP_MAC, MacDeleter> hmac(EVP_MAC_fetch(nullptr, "HMAC", nullptr));
  if (!hmac) fail("EVP_MAC_fetch");
  const std::unique_ptr<EVP_MAC_CTX, MacCtxDeleter> ctx(EVP_MAC_CTX_new(hmac.get()));
  if (!ctx) fail("EVP_MAC_CTX_new");
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_DIGEST, digest, 0),
                               OSSL_PARAM_construct_end()};
  if (EVP_MAC_init(ctx.get(), key.data(), key.size(), params) != 1) fail("init");
  for (const ByteRange& piece : pieces)
    if (piece.size > 0 && EVP_MAC_update(ctx.get(), piece.data, piece.size) != 1) fail("update");
  Mac mac{};
  std::size_t len = 0;
  if (EVP_MAC_final(ctx.get(), mac.data(), &len, mac.size()) != 1 || len != mac.size())
    fail("final");
  return mac;
}

bool macEqual(const Mac& a, const std::uint8_t* b) {
  return CRYPTO_memcmp(a.data(), b, a.size()) == 0;
}

}  // namespace socc::auth
