// GET_CHUNK requests against a small populated map (request checks + chunk query).
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const socc::service::MapService service = socc::fuzz::populatedService();
  if (const auto request = socc::fuzz::decodeRequest<socc::chunk_request_t>(data, size))
    service.getChunk(*request);
  return 0;
}
