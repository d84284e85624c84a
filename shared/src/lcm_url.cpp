#include "socc/lcm_url.hpp"

#include <cstdlib>
#include <sstream>
#include <vector>

namespace socc {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, sep);) parts.push_back(part);
  return parts;
}

bool isNumberInRange(const std::string& s, long lo, long hi) {
  if (s.empty() || s.size() > 5 || s.find_first_not_of("0123456789") != std::string::npos)
    return false;
  const long v = std::strtol(s.c_str(), nullptr, 10);
  return v >= lo && v <= hi;
}

// The values of every ttl= option of the query string.
std::vector<std::string> ttlValues(const std::string& query) {
  std::vector<std::string> values;
  for (const auto& option : split(query, '&'))
    if (option.rfind("ttl=", 0) == 0) values.push_back(option.substr(4));
  return values;
}

// Empty when the ttl options are allowed for auth, else why not (after "refused: ").
std::string checkTtl(const std::string& query, LcmAuth auth) {
  const std::vector<std::string> ttl = ttlValues(query);
  if (ttl.size() != 1)
    return "give exactly one ttl option: ttl=0 keeps traffic on this machine (docs/fleet.md "
           "for ttl=1)";
  if (ttl[0] == "0") return {};
  if (ttl[0] != "1")
    return "ttl=" + ttl[0] + " would let multicast cross routers; socc allows ttl=0 (this " +
           "machine) or ttl=1 (one LAN, with a key)";
  if (auth == LcmAuth::kKeyConfigured) return {};
  return "ttl=1 (LAN) needs an HMAC key, since every host on the link can send to the group: "
         "give --key-file (docs/fleet.md, docs/security.md), or use ttl=0 to stay on this "
         "machine";
}

}  // namespace

std::string checkLcmUrl(const std::string& url, LcmAuth auth) {
  if (url.rfind("memq://", 0) == 0 || url.rfind("file://", 0) == 0) return {};
  const std::string refused = "LCM URL '" + url + "' refused: ";
  const std::string prefix = "udpm://";
  const auto query = url.find('?');
  if (url.rfind(prefix, 0) != 0 || query == std::string::npos)
    return refused + "use udpm://239.x.y.z:port?ttl=0 (or memq://; ttl=1 with a key)";
  const std::string host_port = url.substr(prefix.size(), query - prefix.size());
  const auto colon = host_port.find(':');
  const std::vector<std::string> octets = split(host_port.substr(0, colon), '.');
  bool group_ok = colon != std::string::npos && octets.size() == 4 && octets[0] == "239";
  for (const auto& o : octets) group_ok = group_ok && isNumberInRange(o, 0, 255);
  if (!group_ok || !isNumberInRange(host_port.substr(colon + 1), 1, 65535))
    return refused + "the group must be 239.x.y.z:port (administratively scoped multicast)";
  if (const std::string why = checkTtl(url.substr(query + 1), auth); !why.empty())
    return refused + why;
  return {};
}

bool isLanLcmUrl(const std::string& url) {
  const auto query = url.find('?');
  if (url.rfind("udpm://", 0) != 0 || query == std::string::npos) return false;
  const std::vector<std::string> ttl = ttlValues(url.substr(query + 1));
  return ttl.size() == 1 && ttl[0] == "1";
}

}  // namespace socc
