// GET_STATS requests (header only) through the service handler.
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const socc::service::MapService service = socc::fuzz::populatedService();
  if (const auto request = socc::fuzz::decodeRequest<socc::stats_request_t>(data, size))
    service.getStats(*request, socc::service::RequestCounters{});
  return 0;
}
