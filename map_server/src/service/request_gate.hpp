#pragma once
// The single admission point every decoded request passes before its handler runs.
// map_server uses AuthGate (auth_gate.hpp: HMAC-signed requests, socc/auth/) when it has a key
// and AllowAllGate otherwise.
#include <cstdint>
#include <string>
#include <string_view>

#include "socc/request_header_t.hpp"

namespace socc::service {

class RequestGate {
 public:
  virtual ~RequestGate() = default;
  /// Empty when the request may be handled, else the reason (replied as UNAUTHENTICATED).
  /// data/size are the request exactly as received (for MAC verification).
  virtual std::string admit(std::string_view service, bool state_changing,
                            const request_header_t& header, const std::uint8_t* data, int size) = 0;
};

class AllowAllGate final : public RequestGate {
 public:
  std::string admit(std::string_view, bool, const request_header_t&, const std::uint8_t*,
                    int) override {
    return {};
  }
};

}  // namespace socc::service
