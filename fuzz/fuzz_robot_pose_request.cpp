// GET_ROBOT_POSE requests through the service handler.
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const socc::service::MapService service = socc::fuzz::populatedService();
  if (const auto request = socc::fuzz::decodeRequest<socc::robot_pose_request_t>(data, size))
    service.getRobotPose(*request);
  return 0;
}
