#pragma once
// Guards the network rule: socc programs only talk over memq://, file:// (logs) or UDP
// multicast in 239.0.0.0/8 with ttl=0, so no traffic leaves the machine. LAN mode (ttl=1:
// one hop, the robots and the server on one link, docs/fleet.md) is allowed only to programs
// that have an HMAC key configured (docs/security.md), since every host on the link can then
// send to the group.
#include <string>

namespace socc {

/// Whether the program checking a URL signs or verifies its requests with a shared key.
enum class LcmAuth { kNoKey, kKeyConfigured };

/// kKeyConfigured when key_file names a key (non-empty), else kNoKey.
inline LcmAuth lcmAuthFor(const std::string& key_file) {
  return key_file.empty() ? LcmAuth::kNoKey : LcmAuth::kKeyConfigured;
}

/// Empty string when url is allowed, otherwise the reason it is refused: udpm needs exactly one
/// ttl option, ttl=0 always works, ttl=1 only with auth == kKeyConfigured, nothing else.
std::string checkLcmUrl(const std::string& url, LcmAuth auth = LcmAuth::kNoKey);

/// True for a udpm URL in LAN mode (its one ttl option is ttl=1): large messages are then
/// sent in parts (socc/rpc/part_transport.hpp).
bool isLanLcmUrl(const std::string& url);

}  // namespace socc
