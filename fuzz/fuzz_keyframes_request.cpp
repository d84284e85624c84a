// GET_KEYFRAMES requests through the service handler, with the consistency service on.
#include "fuzz_service.hpp"

namespace {

socc::service::MapService keyframeService() {
  socc::service::ServerConfig config = socc::fuzz::smallServerConfig();
  config.consistency.enabled = true;
  socc::service::MapService svc(config);
  svc.integrate(socc::fuzz::seedScan(1));  // a robot's first integration: its first keyframe
  svc.consistency()->flush();
  return svc;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const socc::service::MapService service = keyframeService();
  if (const auto request = socc::fuzz::decodeRequest<socc::keyframes_request_t>(data, size))
    service.getKeyframes(*request);
  return 0;
}
