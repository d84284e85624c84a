#include "socc/rpc/client_id.hpp"

#include <algorithm>
#include <cctype>

namespace socc::rpc {

std::string checkClientId(const std::string& id) {
  if (id.empty()) return "client id is empty";
  if (id.size() > kMaxClientIdLength)
    return "client id longer than " + std::to_string(kMaxClientIdLength) + " characters";
  const bool safe = std::all_of(id.begin(), id.end(), [](const char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
  if (!safe) return "client id '" + id + "' may only contain A-Z a-z 0-9 _ . -";
  return {};
}

}  // namespace socc::rpc
