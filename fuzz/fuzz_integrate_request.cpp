// Integrate requests as the server receives them: wire guard, checked decode, HMAC
// verification of the raw bytes (socc_auth), then the handler (request checks, map
// validation, integration into a fresh small map).
#include "fuzz_service.hpp"
#include "socc/auth/message_auth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto request = socc::fuzz::decodeRequest<socc::integrate_request_t>(data, size, true);
  if (!request) return 0;
  socc::auth::Verifier verifier(socc::auth::SharedKey::fromBytes(std::vector<std::uint8_t>(32, 7)));
  verifier.verifyEncoded(request->header, data, size);
  verifier.verify(*request);
  socc::service::MapService service(socc::fuzz::smallServerConfig());
  service.integrate(*request);
  service.integrate(*request);  // the retry path (duplicate seq)
  return 0;
}
