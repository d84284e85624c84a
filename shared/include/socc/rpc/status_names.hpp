#pragma once
// Names of the wire codes, so people and scripts read e.g. UNAUTHENTICATED or LOST, not a
// number. The one place they are spelled (socc-cli, odom_client and logs use these).
#include <cstdint>
#include <string>
#include <string_view>

namespace socc::rpc {

/// reply_header_t status, e.g. "FAILED_PRECONDITION"; unknown codes as "status <n>".
std::string statusName(std::int8_t status);
/// robot_status_request_t tracking state, e.g. "LOST"; unknown values as "state <n>".
std::string trackingStateName(std::int8_t state);

/// The end of a RESOURCE_EXHAUSTED message that refuses a request only for its rate (per-robot
/// limits): nothing was applied, and the same request may be sent again a little later
/// (MapClient does). Other RESOURCE_EXHAUSTED refusals (too large an ask) are final.
inline constexpr std::string_view kRateLimited = "slow down";
/// The end of a RESOURCE_EXHAUSTED message that refuses a LOCALIZE search because the server's
/// searches are all taken: nothing was done, and MapClient::localize sends it again until a
/// search is free (within its LOCALIZE timeout).
inline constexpr std::string_view kSearchesBusy = "searches busy, try again";

}  // namespace socc::rpc
