#pragma once
// Client ids become part of LCM channel names (SOCC/<SERVICE>/REP/<client_id>), so both
// sides restrict them to a short, channel-safe alphabet.
#include <string>

namespace socc::rpc {

inline constexpr std::size_t kMaxClientIdLength = 64;

/// Empty when id is 1..64 characters of [A-Za-z0-9_.-], otherwise the reason.
std::string checkClientId(const std::string& id);

}  // namespace socc::rpc
