#pragma once
// Decoding a journal entry (an encoded INTEGRATE) of this or an older server: the current
// integrate_request_t, or its pre-gravity form integrate_request_v1_t (docs/lcm.md "Gravity
// reference"), read as a request without a gravity reference.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "socc/integrate_request_t.hpp"
#include "socc/integrate_request_v1_t.hpp"

namespace socc::service {

/// The request of a pre-gravity entry: the same fields, gravity_sigma 0 (no reference).
integrate_request_t fromPreGravity(integrate_request_v1_t old);

/// nullopt when the bytes are neither form.
std::optional<integrate_request_t> decodeJournalEntry(const std::uint8_t* data, std::size_t size);

}  // namespace socc::service
