// LOCALIZE requests (search and check mode) through the service handler on a small map.
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto request = socc::fuzz::decodeRequest<socc::localize_request_t>(data, size);
  if (!request) return 0;
  socc::service::MapService service = socc::fuzz::populatedService();
  service.localize(*request);
  return 0;
}
