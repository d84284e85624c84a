#pragma once
// Names of the wire codes, so people and scripts read e.g. UNAUTHENTICATED or LOST, not a
// number. The one place they are spelled (socc-cli, odom_client and logs use these).
#include <cstdint>
#include <string>

namespace socc::rpc {

/// reply_header_t status, e.g. "FAILED_PRECONDITION"; unknown codes as "status <n>".
std::string statusName(std::int8_t status);
/// robot_status_request_t tracking state, e.g. "LOST"; unknown values as "state <n>".
std::string trackingStateName(std::int8_t state);

}  // namespace socc::rpc
