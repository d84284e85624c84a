#include "socc/rpc/status_names.hpp"

#include "socc/reply_header_t.hpp"
#include "socc/robot_status_request_t.hpp"

namespace socc::rpc {

std::string statusName(std::int8_t status) {
  switch (status) {
    case reply_header_t::OK:
      return "OK";
    case reply_header_t::INVALID_ARGUMENT:
      return "INVALID_ARGUMENT";
    case reply_header_t::NOT_FOUND:
      return "NOT_FOUND";
    case reply_header_t::RESOURCE_EXHAUSTED:
      return "RESOURCE_EXHAUSTED";
    case reply_header_t::FAILED_PRECONDITION:
      return "FAILED_PRECONDITION";
    case reply_header_t::INTERNAL:
      return "INTERNAL";
    case reply_header_t::UNAUTHENTICATED:
      return "UNAUTHENTICATED";
    default:
      return "status " + std::to_string(status);
  }
}

std::string trackingStateName(std::int8_t state) {
  switch (state) {
    case robot_status_request_t::TRACKING:
      return "TRACKING";
    case robot_status_request_t::DEGRADED:
      return "DEGRADED";
    case robot_status_request_t::LOST:
      return "LOST";
    case robot_status_request_t::RELOCALIZING:
      return "RELOCALIZING";
    default:
      return "state " + std::to_string(state);
  }
}

}  // namespace socc::rpc
