#pragma once
// Guards the network rule: socc programs only talk over memq://, file:// (logs) or UDP
// multicast in 239.0.0.0/8 with ttl=0, so no traffic leaves the machine.
#include <string>

namespace socc {

/// Empty string when url is allowed, otherwise the reason it is refused.
std::string checkLcmUrl(const std::string& url);

}  // namespace socc
