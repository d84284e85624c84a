#pragma once
// LAN access to socc-view: the token a browser must present (?token=... on the page's URL,
// its WebSocket and /foxglove) is derived from the map service's shared key (docs/security.md),
// so whoever may sign map requests may watch, and nobody else; the key never leaves the host.
#include <string>

#include "socc/auth/shared_key.hpp"

namespace socc::view {

/// Hex of HMAC-SHA256(key, "socc-view access v1").
std::string accessToken(const auth::SharedKey& key);

/// Constant-time comparison of a presented token with the expected one.
bool tokenMatches(const std::string& expected, const std::string& presented);

}  // namespace socc::view
