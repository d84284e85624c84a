// GET_CHUNK requests against a small populated map (request checks + chunk query), and the
// reply's structure-of-arrays rows must match its counts, as the router's encode() trusts.
#include "fuzz_service.hpp"
#include "socc/wire_arrays.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const socc::service::MapService service = socc::fuzz::populatedService();
  if (const auto request = socc::fuzz::decodeRequest<socc::chunk_request_t>(data, size)) {
    const socc::chunk_reply_t reply = service.getChunk(*request);
    if (!socc::wire::checkArrays(reply).empty()) __builtin_trap();
  }
  return 0;
}
