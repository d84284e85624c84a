#pragma once
// When MapClient sends a refused request again: the server refuses some requests without
// applying anything and asks for the same request later (status_names.hpp: a robot over its
// rate, all searches taken). One rule per such refusal says how long to pause and for how long
// to keep trying; every other refusal is final and goes back to the caller.
#include <algorithm>
#include <chrono>
#include <initializer_list>
#include <string>
#include <string_view>

#include "socc/reply_header_t.hpp"
#include "socc/rpc/status_names.hpp"

namespace socc::rpc {

struct ResendRule {
  std::string_view tail;             // end of the RESOURCE_EXHAUSTED message of the refusal
  std::chrono::milliseconds step;    // the n-th pause is n * step ...
  std::chrono::milliseconds limit;   // ... but at most limit
  std::chrono::milliseconds within;  // no resend that would start later than this after the call

  std::chrono::milliseconds pause(int refusals) const { return std::min(step * refusals, limit); }
};

/// Over the robot's rate: back off, 10 ms more each time up to 100 ms, for about 5 s.
inline constexpr ResendRule kRateLimitedRule{kRateLimited, std::chrono::milliseconds(10),
                                             std::chrono::milliseconds(100),
                                             std::chrono::milliseconds(5000)};

/// Every search taken: ask again every 250 ms until the LOCALIZE call's own timeout.
inline constexpr ResendRule searchesBusyRule(std::chrono::milliseconds timeout) {
  return {kSearchesBusy, std::chrono::milliseconds(250), std::chrono::milliseconds(250), timeout};
}

/// The index of the rule that refusal (status, message) falls under, or -1: not to be resent.
inline int matchingRule(std::int8_t status, const std::string& message,
                        std::initializer_list<ResendRule> rules) {
  if (status != reply_header_t::RESOURCE_EXHAUSTED) return -1;
  int index = 0;
  for (const ResendRule& rule : rules) {
    if (message.size() >= rule.tail.size() &&
        message.compare(message.size() - rule.tail.size(), rule.tail.size(), rule.tail) == 0)
      return index;
    ++index;
  }
  return -1;
}

}  // namespace socc::rpc
