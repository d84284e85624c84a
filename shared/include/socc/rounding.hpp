#pragma once
// std::lround without the libm call: the wire encoders and the voxel update round hundreds of
// thousands of values a frame, and a call per value was a visible share of a frame's time.
#include <cstdint>

namespace socc {

/// v rounded half away from zero, as std::lround (the same for every float and for doubles not
/// within one ulp below a half), for |v| < 2^62.
inline std::int64_t roundHalfAway(double v) {
  return static_cast<std::int64_t>(v < 0.0 ? v - 0.5 : v + 0.5);
}

}  // namespace socc
