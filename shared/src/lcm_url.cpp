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

}  // namespace

std::string checkLcmUrl(const std::string& url) {
  if (url.rfind("memq://", 0) == 0 || url.rfind("file://", 0) == 0) return {};
  const std::string refused = "LCM URL '" + url + "' refused: ";
  const std::string prefix = "udpm://";
  const auto query = url.find('?');
  if (url.rfind(prefix, 0) != 0 || query == std::string::npos)
    return refused + "use udpm://239.x.y.z:port?ttl=0 (or memq://)";
  const std::string host_port = url.substr(prefix.size(), query - prefix.size());
  const auto colon = host_port.find(':');
  const std::vector<std::string> octets = split(host_port.substr(0, colon), '.');
  bool group_ok = colon != std::string::npos && octets.size() == 4 && octets[0] == "239";
  for (const auto& o : octets) group_ok = group_ok && isNumberInRange(o, 0, 255);
  if (!group_ok || !isNumberInRange(host_port.substr(colon + 1), 1, 65535))
    return refused + "the group must be 239.x.y.z:port (administratively scoped multicast)";
  for (const auto& option : split(url.substr(query + 1), '&'))
    if (option == "ttl=0") return {};
  return refused + "ttl=0 is required so traffic stays on this machine";
}

}  // namespace socc
