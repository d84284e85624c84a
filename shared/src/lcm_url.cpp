#include "socc/lcm_url.hpp"

#include <regex>

namespace socc {

std::string checkLcmUrl(const std::string& url) {
  if (url.rfind("memq://", 0) == 0 || url.rfind("file://", 0) == 0) return {};
  static const std::regex kUdpm(R"(^udpm://239\.(\d{1,3})\.(\d{1,3})\.(\d{1,3}):(\d{1,5})\?(.*)$)");
  std::smatch m;
  if (!std::regex_match(url, m, kUdpm))
    return "LCM URL '" + url + "' refused: use udpm://239.x.y.z:port?ttl=0 (or memq://)";
  for (int i = 1; i <= 3; ++i)
    if (std::stoi(m[i].str()) > 255) return "LCM URL '" + url + "': bad multicast address";
  static const std::regex kTtl0(R"((^|&)ttl=0($|&))");
  if (!std::regex_search(m[5].str(), kTtl0))
    return "LCM URL '" + url + "' refused: ttl=0 is required so traffic stays on this machine";
  return {};
}

}  // namespace socc
