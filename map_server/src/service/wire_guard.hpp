#pragma once
// Pre-decode sanity check of untrusted request bytes. The generated LCM decode() allocates
// arrays from the encoded counts BEFORE checking them against the buffer, so a 100-byte
// message claiming 2^31 points would allocate tens of GB. These checks walk the encoding
// and refuse counts that cannot fit in the received bytes.
#include <string>
#include <string_view>

namespace socc::service {

/// Empty when every variable-length field of the request header fits in [data, data+size).
/// Works for all request types: each begins with request_header_t after the type hash.
std::string checkRequestHeaderWire(const void* data, int size);

/// As above, plus the point/label/time arrays of an integrate_request_t.
std::string checkIntegrateWire(const void* data, int size);

}  // namespace socc::service
