#include "journal_entry.hpp"

#include "socc/rpc/safe_decode.hpp"

namespace socc::service {

std::optional<integrate_request_t> decodeJournalEntry(const std::uint8_t* data, std::size_t size) {
  const int n = static_cast<int>(size);
  if (auto request = rpc::safeDecode<integrate_request_t>(data, n)) return request;
  // Each form carries its own fingerprint: older bytes never decode as a newer type.
  if (auto old = rpc::safeDecode<integrate_request_v2_t>(data, n)) return upgraded(std::move(*old));
  if (auto old = rpc::safeDecode<integrate_request_v1_t>(data, n)) return upgraded(std::move(*old));
  return std::nullopt;
}

}  // namespace socc::service
