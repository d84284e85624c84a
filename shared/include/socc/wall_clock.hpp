#pragma once
// Wall-clock time in microseconds since the Unix epoch: the utime of LCM messages and log events.
#include <chrono>
#include <cstdint>

namespace socc {

inline std::int64_t nowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace socc
