// ROBOT_STATUS requests through the service handler, then an INTEGRATE of the same robot,
// which the reported state may refuse.
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto request = socc::fuzz::decodeRequest<socc::robot_status_request_t>(data, size);
  if (!request) return 0;
  socc::service::MapService service = socc::fuzz::populatedService();
  request->header.client_id = "seed";  // the robot the populated map knows
  service.robotStatus(*request);
  service.integrate(socc::fuzz::seedScan(2));
  return 0;
}
